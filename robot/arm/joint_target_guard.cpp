// SPDX-License-Identifier: MIT
/// @brief JointTargetGuard (see joint_target_guard.h).
#include "robot/arm/joint_target_guard.h"

#include <algorithm>
#include <cmath>

namespace telesphere::robot::arm {

void JointTargetGuard::startFrom(const JointVector& q, std::int64_t now_ns) {
  last_target_ = q;
  last_target_ns_ = now_ns;
  consecutive_jumps_ = 0;
}

JointTargetGuard::Verdict JointTargetGuard::check(const JointVector& q_target, std::int64_t now_ns) {
  if (!kinematics_.withinLimits(q_target)) return Verdict::kOutsideLimits;
  if (last_target_) {
    const double dt_s =
        double(std::clamp(now_ns - last_target_ns_, options_.period_ns, 3 * options_.period_ns)) * 1e-9;
    const JointVector step = (q_target - *last_target_).cwiseAbs();
    int joint = 0;
    const double largest = step.maxCoeff(&joint);
    if (largest > options_.max_velocity * dt_s + 1e-3) {
      if (++consecutive_jumps_ < options_.refused_jumps_for_fault) return Verdict::kJump;
      const auto deg = [](double rad) { return std::to_string(int(std::lround(rad * 180 / M_PI))); };
      fault_ = "targets jump: J" + std::to_string(joint + 1) + " by " + deg(largest) + "° in " +
               std::to_string(int(std::lround(dt_s * 1e3))) + " ms (the joints' top speed allows " +
               deg(options_.max_velocity * dt_s) + "°); clear the fault to resume from where the arm is";
      return Verdict::kJumpFault;
    }
  }
  consecutive_jumps_ = 0;
  last_target_ = q_target;
  last_target_ns_ = now_ns;
  return Verdict::kAccepted;
}

}  // namespace telesphere::robot::arm
