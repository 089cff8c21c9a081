// SPDX-License-Identifier: MIT
/// @brief HeadLoop: arm ↔ joint-state buffer ↔ controller ↔ link, once per period.
#include "robot/head_loop.h"

#include "robot/link/link_pose.h"

#include <chrono>
#include <cmath>
#include <iostream>
#include <thread>

namespace telesphere::robot {

std::optional<HeadMode> headModeFromName(const std::string& name) {
  if (name == "full6d") return HeadMode::kFull6D;
  if (name == "orientation3d") return HeadMode::kOrientationOnly;
  if (name == "fixed") return HeadMode::kFixed;
  return std::nullopt;
}

const char* headModeName(HeadMode mode) {
  switch (mode) {
    case HeadMode::kFull6D: return "full6d";
    case HeadMode::kOrientationOnly: return "orientation3d";
    case HeadMode::kFixed: return "fixed";
  }
  return "full6d";
}

HeadLoop::HeadLoop(HeadArm& arm, HeadController& controller, JointStateBuffer& buffer,
                   link::LinkServer& server, const Clock& clock, const HeadLoopConfig& config)
    : arm_(arm),
      controller_(controller),
      buffer_(buffer),
      server_(server),
      clock_(clock),
      config_(config),
      sphere_radius_(config.sphere_radius) {}

std::optional<JointState> HeadLoop::lastState() const {
  std::lock_guard lock(mutex_);
  return last_state_;
}

void HeadLoop::tick() {
  const std::int64_t now_ns = clock_.nowNs();
  std::lock_guard lock(mutex_);
  arm_.update();
  while (auto state = arm_.pollState()) {
    buffer_.push(*state);
    last_state_ = *state;
  }

  // The newest head target, if it is new: stamped with its arrival here (see the header).
  std::optional<HmdSample> sample;
  if (auto target = server_.latestHeadTarget(); target && target->valid() &&
                                                target->t_ns() != last_target_t_ns_) {
    last_target_t_ns_ = target->t_ns();
    sample = HmdSample{now_ns, link::fromLinkPose(target->t_vr_hmd())};
    last_sample_ = sample;
  }
  const bool want_nominal =
      pending_nominal_ || (config_.auto_nominal && !controller_.initialised());
  if (want_nominal && last_sample_ && last_state_) {
    if (controller_.initialise(*last_sample_, last_state_->q)) {
      pending_nominal_ = false;
      std::cerr << "telesphere-robot: nominal pose captured\n";
    }
  }

  const HeadCommand command = controller_.tick(sample, now_ns);
  if (command.send && arm_.sendTarget(command.q_target)) ++targets_sent_;

  const std::int64_t tick = ticks_++;
  if (config_.state_every_ticks > 0 && tick % config_.state_every_ticks == 0 && last_state_) {
    link::proto::RobotState state;
    state.set_t_ns(last_state_->t_ns);
    for (int i = 0; i < 6; ++i) state.add_joint_positions(last_state_->q[i]);
    link::toLinkPose(controller_.kinematics().forward(last_state_->q), state.mutable_t_robot_flange());
    state.set_mode(headModeName(controller_.mode()));
    const ArmStatus status = arm_.status();
    state.set_arm_ok(status == ArmStatus::kOk);
    if (status == ArmStatus::kStopped) state.set_fault("arm stopped (fault or emergency stop)");
    if (status == ArmStatus::kDisconnected) state.set_fault("arm disconnected");
    state.set_sphere_radius(sphere_radius_);
    state.set_nominal_set(controller_.initialised());
    if (controller_.initialised()) link::toLinkPose(controller_.T_robot_vr(), state.mutable_t_robot_vr());
    server_.publishRobotState(state);
  }
}

void HeadLoop::run(const std::atomic<bool>& stop) {
  auto next = std::chrono::steady_clock::now();
  while (!stop.load()) {
    tick();
    next += std::chrono::nanoseconds(config_.period_ns);
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // overran: do not try to catch up with a burst of ticks
    std::this_thread::sleep_until(next);
  }
}

link::proto::ControlReply HeadLoop::handleControl(const link::proto::ControlRequest& request) {
  link::proto::ControlReply reply;
  reply.set_id(request.id());
  reply.set_ok(true);
  std::lock_guard lock(mutex_);
  switch (request.request_case()) {
    case link::proto::ControlRequest::kSetMode: {
      const auto mode = headModeFromName(request.set_mode());
      if (!mode) {
        reply.set_ok(false);
        reply.set_error("unknown mode '" + request.set_mode() + "' (full6d, orientation3d, fixed)");
      } else {
        controller_.setMode(*mode);
      }
      break;
    }
    case link::proto::ControlRequest::kCaptureNominal:
      if (!last_sample_) {
        reply.set_ok(false);
        reply.set_error("no head target received yet: put the headset on and try again");
      } else {
        pending_nominal_ = true;  // taken by the next tick, which has the newest joint state
      }
      break;
    case link::proto::ControlRequest::kSetSphereRadius: {
      const double r = request.set_sphere_radius();
      if (!(std::isfinite(r) && r >= 0.05 && r <= 1000.0)) {
        reply.set_ok(false);
        reply.set_error("sphere radius " + std::to_string(r) + " m is outside [0.05, 1000]");
      } else {
        sphere_radius_ = r;
      }
      break;
    }
    case link::proto::ControlRequest::kCalibrationCapture:
      reply.set_ok(false);
      reply.set_error("calibration capture is not available in this build (use telesphere-calib)");
      break;
    default:
      reply.set_ok(false);
      reply.set_error("empty control request");
  }
  return reply;
}

}  // namespace telesphere::robot
