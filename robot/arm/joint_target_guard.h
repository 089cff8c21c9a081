// SPDX-License-Identifier: MIT
/// @brief The arm driver's last safety rule before a joint target leaves for the controller: a
///        target outside the joint limits or not finite is refused; so is one further from the
///        previous accepted target than the joints' top speed allows in the time since (that time
///        taken as at least one and at most three report periods, so a late tick does not widen
///        the limit and an early one does not narrow it). N refused jumps in a row are a fault,
///        with a text that names the joint, the step and the limit. An accepted target resets the
///        count. No sockets, no threads, no clock of its own: XArmHeadArm calls it under its lock.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot::arm {

struct JointTargetGuardOptions {
  double max_velocity = 3.14159265358979323846;  ///< rad/s: the joints' top speed
  std::int64_t period_ns = 10'000'000;           ///< the target stream's period (the reports')
  int refused_jumps_for_fault = 10;              ///< this many refused jumps in a row: a fault
};

class JointTargetGuard {
 public:
  enum class Verdict {
    kAccepted,       ///< send it; it is the reference for the next one
    kOutsideLimits,  ///< not finite or outside the joint limits (the jump count is unchanged)
    kJump,           ///< too far from the previous target
    kJumpFault,      ///< too far, and the N-th in a row: fault() says why
  };

  explicit JointTargetGuard(const JointTargetGuardOptions& options = {}) : options_(options) {}

  /// The reference is where the arm is now (streaming starts or resumes there); the count restarts.
  void startFrom(const JointVector& q, std::int64_t now_ns);
  /// The verdict on `q_target` at `now_ns`; an accepted target becomes the reference.
  Verdict check(const JointVector& q_target, std::int64_t now_ns);

  /// Why the last kJumpFault was one ("targets jump: J2 by 45° in 10 ms (… allows 2°) …").
  const std::string& fault() const { return fault_; }
  int consecutiveJumps() const { return consecutive_jumps_; }
  const std::optional<JointVector>& reference() const { return last_target_; }

 private:
  JointTargetGuardOptions options_;
  Xarm6Kinematics kinematics_;
  std::optional<JointVector> last_target_;
  std::int64_t last_target_ns_ = 0;
  int consecutive_jumps_ = 0;
  std::string fault_;
};

}  // namespace telesphere::robot::arm
