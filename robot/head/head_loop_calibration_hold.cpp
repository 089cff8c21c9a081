// SPDX-License-Identifier: MIT
/// @brief HeadLoop's calibration holds: the head held at a wizard's pose (or moving along the
///        calibration head pattern) under a lease its holder renews; released on request or when
///        the holder goes silent, never for the robot's own silence.
#include "robot/head/head_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "robot/head/calibration_head_pattern.h"
#include "robot/link/head_angles.h"
#include "robot/link/link_pose.h"

namespace telesphere::robot::head {

void HeadLoop::controlStarted() { ++controls_in_progress_; }

void HeadLoop::controlFinished() {
  control_finished_ns_ = clock_.nowNs();
  --controls_in_progress_;
}

link::proto::HeadHold HeadLoop::hold() const {
  std::lock_guard lock(mutex_);
  return holdLocked();
}

link::proto::HeadHold HeadLoop::holdLocked() const {
  link::proto::HeadHold h;
  h.set_lease_s(double(config_.hold_lease_ns) * 1e-9);
  h.set_last_release(last_release_);
  if (!hold_) return h;
  h.set_lease(hold_->lease);
  h.set_holder(hold_->holder);
  h.set_pattern_amplitude_deg(pattern_ ? pattern_->amplitude_deg : 0.0);
  h.set_since_ns(hold_->since_ns);
  h.set_renewed_ns(hold_->renewed_ns);
  return h;
}

void HeadLoop::releaseHoldLocked(const std::string& how) {
  if (!hold_) return;
  controller_.releaseHold();
  last_release_ = hold_->holder + "'s hold (lease " + std::to_string(hold_->lease) + ") " + how;
  std::cerr << "telesphere-robot: calibration head hold: " << last_release_ << '\n';
  hold_.reset();
  pattern_.reset();
}

void HeadLoop::expireHoldLocked(std::int64_t now_ns) {
  if (!hold_ || controls_in_progress_.load() > 0) return;
  // The robot's own silence (serving a long request) does not count against the holder.
  const std::int64_t heard_ns = std::max(hold_->renewed_ns, control_finished_ns_.load());
  if (now_ns - heard_ns <= config_.hold_lease_ns) return;
  char how[120];
  std::snprintf(how, sizeof how, "released: not renewed for %.1f s (its holder went silent)",
                double(now_ns - hold_->renewed_ns) * 1e-9);
  releaseHoldLocked(how);
}

bool HeadLoop::calibrationHoldLocked(const link::proto::CalibrationHeadPose& request, std::string* error) {
  const std::int64_t now_ns = clock_.nowNs();
  if (request.release()) {
    // With a lease: that hold only (a late release of an ended hold changes nothing); without:
    // any (the supervisor's "release head").
    if (hold_ && (request.lease() == 0 || request.lease() == hold_->lease))
      releaseHoldLocked(request.lease() == 0 ? "released by " + (request.holder().empty() ? std::string("the console")
                                                                                          : request.holder())
                                             : std::string("released by its holder"));
    return true;
  }
  if (request.renew()) {
    if (!hold_ || hold_->lease != request.lease()) {
      *error = "no calibration hold with lease " + std::to_string(request.lease()) + " to renew" +
               (last_release_.empty() ? std::string() : " (last: " + last_release_ + ")");
      return false;
    }
    hold_->renewed_ns = now_ns;
    return true;
  }
  if (hold_ && request.lease() != hold_->lease) {
    *error = "the head is held for calibration by " + hold_->holder + " (lease " + std::to_string(hold_->lease) +
             "): wait for it, or release the head from the console";
    return false;
  }
  if (!hold_ && request.lease() != 0) {
    *error = "no calibration hold with lease " + std::to_string(request.lease()) +
             (last_release_.empty() ? std::string() : " (last: " + last_release_ + ")");
    return false;
  }
  if (!hold_ && request.holder().empty()) {
    *error = "a calibration hold needs a holder (who asks, for the supervisor)";
    return false;
  }
  if (step_ != link::proto::NOMINAL_STEP_FOLLOWING) {
    *error = "the nominal-pose step is running: finish or undo it first";
    return false;
  }
  if (!last_state_) {
    *error = "no joint state from the arm yet";
    return false;
  }
  if (!armOkLocked()) {
    *error = "the arm is not ready (" + faultLocked() + "): clear the fault first";
    return false;
  }
  const double amplitude = request.pattern_amplitude_deg();
  if (!(amplitude >= 0.0 && amplitude <= kMaxCalibrationPatternDeg)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "calibration head pattern: amplitude %g deg is outside [0, %g]", amplitude,
                  kMaxCalibrationPatternDeg);
    *error = buf;
    return false;
  }
  if (!request.has_t_robot_head() && amplitude == 0.0) {
    *error = "calibration head pose: no pose given";
    return false;
  }
  // A pattern without a pose runs about the nominal pose.
  const Eigen::Isometry3d T_robot_head =
      request.has_t_robot_head() ? link::fromLinkPose(request.t_robot_head()) : controller_.config().T_robot_nom;
  if (!T_robot_head.matrix().allFinite()) {
    *error = "calibration head pose: not a finite pose";
    return false;
  }
  const Eigen::AlignedBox3d& workspace = controller_.config().workspace;
  if (!workspace.contains(T_robot_head.translation())) {
    const Eigen::Vector3d p = T_robot_head.translation();
    char buf[200];
    std::snprintf(buf, sizeof buf, "calibration head pose: position (%.3f, %.3f, %.3f) m is outside the head workspace",
                  p.x(), p.y(), p.z());
    *error = buf;
    return false;
  }
  const arm::IkResult ik = controller_.reachAlongApproach(T_robot_head, last_state_->q);
  if (ik.status != arm::IkResult::Status::kConverged) {
    *error = "calibration head pose: the arm cannot reach it";
    return false;
  }
  // Every pose of the pattern must be reachable too: check its extremes.
  for (const double yaw : {-1.0, 1.0})
    for (const double pitch : {-1.0, 1.0})
      for (const double roll : {-1.0, 1.0}) {
        if (amplitude == 0.0) continue;
        const Eigen::Isometry3d T = calibrationPatternSwing(T_robot_head, amplitude * M_PI / 180.0, yaw, pitch, roll);
        if (controller_.kinematics().inverse(T * T_flange_head_.inverse(), ik.q, controller_.config().ik).status !=
            arm::IkResult::Status::kConverged) {
          *error = "calibration head pattern: the arm cannot reach its extremes at this amplitude";
          return false;
        }
      }
  if (!controller_.holdAt(T_robot_head, last_state_->q, clock_.nowNs())) {
    *error = "calibration head pose: not a rigid transform";
    return false;
  }
  if (amplitude > 0.0) {
    pattern_ = HeadPattern{T_robot_head, amplitude, clock_.nowNs()};
    std::cerr << "telesphere-robot: calibration head pattern started (" << amplitude << " deg)\n";
  } else {
    pattern_.reset();
  }
  if (!hold_) {
    hold_ = CalibrationHold{next_lease_++, request.holder(), now_ns, now_ns};
    std::cerr << "telesphere-robot: calibration head hold by " << hold_->holder << " (lease " << hold_->lease << ")\n";
  }
  hold_->renewed_ns = now_ns;
  return true;
}

}  // namespace telesphere::robot::head
