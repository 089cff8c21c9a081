// SPDX-License-Identifier: MIT
/// @brief The head-arm seam (DESIGN.md §5, STYLE.md §2): timestamped joint states out, joint
///        targets in, at 100 Hz. Implementations: SimulatedArm (robot/arm/head_arm_sim.h); a real
///        xArm driver implements the same interface.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "robot/arm/joint_state.h"

namespace telesphere::robot::arm {

class HeadArm {
 public:
  /// The state and command rate of the arm: 100 Hz (paper §V, modified xArm firmware).
  static constexpr std::int64_t kStatePeriodNs = 10'000'000;

  virtual ~HeadArm() = default;

  /// Does the arm's I/O up to now: receives states, sends pending targets (the simulated arm also
  /// advances its physics to its clock's now). Call at least at the state rate.
  virtual void update() = 0;

  /// Asks the arm to move to q_target (rad) as fast as its limits allow. Returns false, and the
  /// target is dropped, when the arm is stopped or disconnected, or when q_target is not finite
  /// or outside the joint limits (the arm refuses such targets, so callers must clamp first).
  virtual bool sendTarget(const JointVector& q_target) = 0;

  /// The oldest joint state not yet taken, in time order; empty when none has arrived.
  virtual std::optional<JointState> pollState() = 0;

  /// The arm's status as last known.
  virtual ArmStatus status() const = 0;

  /// A protective stop on request (the console's stop button): the arm brakes within its limits
  /// and holds; targets are refused (status kStopped) until clearStop().
  virtual void stop() = 0;

  /// Clears a stop (ArmStatus::kStopped) so that targets are followed again; false if the arm
  /// cannot be re-enabled now (e.g. disconnected). An arm that can reconnect does so here, and
  /// only here: the supervisor's "clear fault" is the request. It may take seconds (an xArm
  /// reconnecting): the head loop runs it on a thread of its own (ArmRecovery) and calls nothing
  /// else on the arm meanwhile. The arm may have moved or braked while it was stopped: whoever
  /// commands it next starts from a joint state measured after this returned.
  virtual bool clearStop() = 0;

  /// Why the arm is not kOk, in words for the console ("xArm controller error 22: self-collision
  /// detected", "no joint report for 120 ms"); kStoppedOnRequest when stop() is the only reason;
  /// empty when there is nothing to say beyond status(). A fault of the arm's own that comes
  /// after a stop on request replaces kStoppedOnRequest.
  virtual std::string faultText() const { return {}; }

  /// faultText() of an arm that is stopped only because stop() asked.
  static constexpr const char* kStoppedOnRequest = "stopped on request";
};

}  // namespace telesphere::robot::arm
