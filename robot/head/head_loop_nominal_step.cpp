// SPDX-License-Identifier: MIT
/// @brief HeadLoop's nominal-pose step (HOLD → CAPTURE → CONFIRM, UNDO; the headset's one-shot capture): the
///        state machine of head_loop.h's file comment, under the loop's lock.
#include "robot/head/head_loop.h"

#include <cmath>
#include <iostream>

#include "robot/link/head_angles.h"
#include "robot/link/link_pose.h"

namespace telesphere::robot::head {

link::proto::NominalMapping HeadLoop::nominalMapping() const {
  std::lock_guard lock(mutex_);
  return nominalMappingLocked();
}

link::proto::NominalMapping HeadLoop::nominalMappingLocked() const {
  link::proto::NominalMapping m;
  m.set_step(step_);
  m.set_has_previous(step_ != link::proto::NOMINAL_STEP_FOLLOWING ? controller_.initialised()
                                                                   : previous_mapping_.has_value());
  const std::optional<ArrivedTarget>& shown = step_ == link::proto::NOMINAL_STEP_CAPTURED ? captured_ : std::nullopt;
  if (shown) {
    link::toLinkPose(controller_.mappingFor(shown->sample.T_vr_hmd), m.mutable_t_robot_vr());
    m.set_mapping_set(true);
  } else if (controller_.initialised()) {
    link::toLinkPose(controller_.T_robot_vr(), m.mutable_t_robot_vr());
    m.set_mapping_set(true);
  }
  if (shown) {
    link::toLinkPose(shown->sample.T_vr_hmd, m.mutable_t_vr_hmd_captured());
    const link::HeadAngles a = link::headAnglesOf(shown->sample.T_vr_hmd);
    m.set_yaw_deg(a.yaw * 180.0 / M_PI);
    m.set_pitch_deg(a.pitch * 180.0 / M_PI);
    m.set_roll_deg(a.roll * 180.0 / M_PI);
  }
  return m;
}

bool HeadLoop::applyNominalLocked(const HmdSample& nominal) {
  const std::optional<Eigen::Isometry3d> before =
      controller_.initialised() ? std::optional(controller_.T_robot_vr()) : std::nullopt;
  if (!controller_.initialise(nominal, last_state_->q)) return false;
  previous_mapping_ = before;
  return true;
}

bool HeadLoop::captureNominalLocked(std::string* error) {
  const std::int64_t now_ns = clock_.nowNs();
  if (!last_target_) {
    *error = "no head pose from the XR app yet: is telesphere-xr running and the headset on?";
    return false;
  }
  const std::int64_t age_ns = now_ns - last_target_->sample.t_ns;
  if (age_ns > config_.max_capture_age_ns) {
    *error = "no fresh head pose from the XR app: the newest is " + std::to_string(age_ns / 1'000'000) +
             " ms old (at most " + std::to_string(config_.max_capture_age_ns / 1'000'000) +
             " ms): is the headset tracking?";
    return false;
  }
  captured_ = last_target_;
  step_ = link::proto::NOMINAL_STEP_CAPTURED;
  return true;
}

bool HeadLoop::nominalStepLocked(link::proto::NominalStepRequest request, std::string* error) {
  using link::proto::NominalStep;
  switch (request) {
    case link::proto::NOMINAL_REQUEST_HOLD:
      if (hold_) {
        *error = "the head is held for calibration by " + hold_->holder + ": release it first";
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
      controller_.holdNominal(last_state_->q, clock_.nowNs());
      captured_.reset();
      step_ = link::proto::NOMINAL_STEP_HOLDING;
      return true;
    case link::proto::NOMINAL_REQUEST_CAPTURE:
      if (step_ == link::proto::NOMINAL_STEP_FOLLOWING) {
        *error = "hold the head at the nominal pose first (step HOLD)";
        return false;
      }
      return captureNominalLocked(error);
    case link::proto::NOMINAL_REQUEST_CONFIRM: {
      if (step_ != link::proto::NOMINAL_STEP_CAPTURED || !captured_) {
        *error = "nothing captured to confirm";
        return false;
      }
      if (!last_state_) {
        *error = "no joint state from the arm yet";
        return false;
      }
      if (!applyNominalLocked(captured_->sample)) {
        *error = "the captured head pose is not a valid pose";
        return false;
      }
      controller_.releaseHold();
      captured_.reset();
      step_ = link::proto::NOMINAL_STEP_FOLLOWING;
      std::cerr << "telesphere-robot: nominal pose confirmed\n";
      return true;
    }
    case link::proto::NOMINAL_REQUEST_UNDO:
      if (step_ != link::proto::NOMINAL_STEP_FOLLOWING) {
        captured_.reset();
        controller_.releaseHold();
        step_ = link::proto::NOMINAL_STEP_FOLLOWING;
        return true;
      }
      if (!previous_mapping_) {
        *error = "nothing to undo: no earlier nominal pose";
        return false;
      }
      controller_.restoreMapping(*previous_mapping_);
      previous_mapping_.reset();
      std::cerr << "telesphere-robot: nominal pose undone\n";
      return true;
    default:
      *error = "unknown nominal step request";
      return false;
  }
}

}  // namespace telesphere::robot::head
