// SPDX-License-Identifier: MIT
/// @brief HeadLoop: arm ↔ joint-state buffer ↔ controller ↔ link, once per period.
#include "robot/head/head_loop.h"

#include "robot/head/calibration_head_pattern.h"

#include "robot/link/head_angles.h"
#include "robot/link/link_pose.h"
#include "robot/link/proto_enums.h"
#include "robot/link/sphere_radius.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <thread>

namespace telesphere::robot::head {


HeadLoop::HeadLoop(arm::HeadArm& arm, HeadController& controller, JointStateBuffer& buffer,
                   link::LinkServer& server, const clock::Clock& clock, const HeadLoopConfig& config)
    : arm_(arm),
      controller_(controller),
      buffer_(buffer),
      server_(server),
      clock_(clock),
      config_(config),
      T_flange_head_(controller.config().geometry.T_flange_head()),
      recovery_(arm),
      sphere_radius_(config.sphere_radius),
      depth_proxy_(config.depth_proxy) {}

std::optional<arm::JointState> HeadLoop::lastState() const {
  std::lock_guard lock(mutex_);
  return last_state_;
}

link::proto::NominalStep HeadLoop::nominalStep() const {
  std::lock_guard lock(mutex_);
  return step_;
}

void HeadLoop::tick() {
  const std::int64_t now_ns = clock_.nowNs();
  std::lock_guard lock(mutex_);
  if (!recovery_.running()) {
    arm_.update();
    while (auto state = arm_.pollState()) {
      buffer_.push(*state);
      last_state_ = *state;
    }
  }
  followArmLocked(now_ns);
  const bool follow = armOkLocked() && !resume_pending_;
  if (config_.calibration) {
    const std::shared_ptr<const AppliedCalibration> in_use = config_.calibration->current();
    if (in_use->generation != calibration_generation_) {
      controller_.setGeometry(in_use->geometry);
      buffer_.setGeometry(in_use->geometry);
      T_flange_head_ = in_use->geometry.T_flange_head();
      if (calibration_generation_ != 0)
        std::cerr << "telesphere-robot: calibration generation " << in_use->generation << " in use (" << in_use->source
                  << ")\n";
      calibration_generation_ = in_use->generation;
    }
  }

  // The newest head target, if it is new, at its sampling time in the robot clock (see the header).
  std::optional<HmdSample> sample;
  if (auto target = server_.latestHeadTarget();
      target && target->valid() &&
      (target->sender_instance() != last_target_sender_ || target->t_ns() != last_target_t_ns_)) {
    last_target_sender_ = target->sender_instance();
    last_target_t_ns_ = target->t_ns();
    const bool clock_known = target->t_robot_ns() != 0;
    if (!clock_known) ++targets_stamped_on_arrival_;
    sample = HmdSample{clock_known ? target->t_robot_ns() : now_ns, link::fromLinkPose(target->t_vr_hmd())};
    last_target_ = ArrivedTarget{*sample, target->t_robot_ns(), now_ns};
  }
  const bool want_nominal =
      pending_nominal_ || (config_.auto_nominal && !controller_.initialised() &&
                           step_ == link::proto::NOMINAL_STEP_FOLLOWING);
  if (want_nominal && last_target_ && last_state_ && applyNominalLocked(last_target_->sample)) {
    pending_nominal_ = false;
    std::cerr << "telesphere-robot: nominal pose captured\n";
  }

  expireHoldLocked(now_ns);
  if (hold_ && pattern_) {
    controller_.moveHold(calibrationPatternPose(pattern_->T_robot_centre, pattern_->amplitude_deg,
                                                now_ns - pattern_->start_ns));
  }
  // The head's measured pose, once per tick (telemetry and robot state both carry it).
  const std::optional<Eigen::Isometry3d> T_robot_head_measured =
      last_state_ ? std::optional(controller_.kinematics().forward(last_state_->q) * T_flange_head_) : std::nullopt;
  HeadCommand command;  // while the arm is not ok: nothing sent, the head where it was measured
  if (follow) {
    command = controller_.tick(sample, now_ns);
  } else {
    command.send = false;
    if (T_robot_head_measured) command.T_robot_headTarget = *T_robot_head_measured;
  }
  const bool accepted = follow && command.send && arm_.sendTarget(command.q_target);
  if (accepted) ++targets_sent_;

  if (config_.telemetry) {
    link::proto::HeadTick t;
    t.set_t_ns(now_ns);
    t.set_outcome(accepted                    ? link::proto::HEAD_TICK_SENT
                  : command.send || !follow   ? link::proto::HEAD_TICK_ARM_REFUSED
                  : command.reason == HeadRejectReason::kNotInitialised ? link::proto::HEAD_TICK_NOT_INITIALISED
                  : command.reason == HeadRejectReason::kMissing        ? link::proto::HEAD_TICK_NO_TARGET
                                                                        : link::proto::HEAD_TICK_REJECTED);
    t.set_target_new(sample.has_value());
    if (sample) {
      t.set_target_t_ns(last_target_->sampled_robot_ns);
      t.set_target_arrival_ns(last_target_->arrival_ns);
    }
    link::toLinkPose(command.T_robot_headTarget, t.mutable_t_robot_head_command());
    if (last_state_) {
      link::toLinkPose(*T_robot_head_measured, t.mutable_t_robot_head_measured());
      t.set_joint_state_ns(last_state_->t_ns);
    }
    t.set_approaching(command.approaching);
    t.set_clamped(command.clamped);
    t.set_unreachable(command.send && command.ik_status == arm::IkResult::Status::kClosestReachable);
    config_.telemetry->addTick(t);
  }

  const std::int64_t tick = ticks_++;
  if (config_.telemetry && config_.telemetry_every_ticks > 0 &&
      (tick + 1) % config_.telemetry_every_ticks == 0) {
    if (auto batch = config_.telemetry->takeBatch()) server_.publishTelemetry(*batch);
  }
  if (config_.state_every_ticks > 0 && tick % config_.state_every_ticks == 0 && last_state_) {
    link::proto::RobotState state;
    state.set_t_ns(last_state_->t_ns);
    for (int i = 0; i < 6; ++i) state.add_joint_positions(last_state_->q[i]);
    link::toLinkPose(controller_.kinematics().forward(last_state_->q), state.mutable_t_robot_flange());
    state.set_visual_mode(link::toProto(controller_.mode()));
    state.set_nominal_step(step_);
    state.set_arm_ok(armOkLocked());
    state.set_fault(faultLocked());
    state.set_sphere_radius(sphere_radius_);
    if (depth_proxy_) state.set_depth_proxy(link::toProto(*depth_proxy_));
    state.set_nominal_set(controller_.initialised());
    if (controller_.initialised()) link::toLinkPose(controller_.T_robot_vr(), state.mutable_t_robot_vr());
    link::toLinkPose(*T_robot_head_measured, state.mutable_t_robot_head());
    state.set_calibration_hold(hold_.has_value());
    *state.mutable_hold() = holdLocked();
    state.set_calibration_generation(calibration_generation_);
    if (trial_.running()) {
      *state.mutable_trial() = trial_;
      state.mutable_trial()->set_elapsed_s(trial_.elapsed_s() + double(clock_.nowNs() - trial_received_ns_) * 1e-9);
    }
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

bool HeadLoop::armOkLocked() const { return !recovery_.running() && arm_.status() == arm::ArmStatus::kOk; }

void HeadLoop::followArmLocked(std::int64_t now_ns) {
  if (recovery_.running()) {
    resume_pending_ = true;
    arm_ok_since_ns_ = 0;
    return;
  }
  if (const auto outcome = recovery_.takeOutcome()) {
    if (*outcome) {
      stopped_by_console_ = false;
      std::cerr << "telesphere-robot: arm fault cleared\n";
    } else {
      std::cerr << "telesphere-robot: the arm's fault was not cleared: " << faultLocked() << '\n';
    }
    if (stop_after_recovery_) {
      stop_after_recovery_ = false;
      arm_.stop();
      stopped_by_console_ = true;
    }
  }
  if (arm_.status() != arm::ArmStatus::kOk) {
    resume_pending_ = true;
    arm_ok_since_ns_ = 0;
    return;
  }
  if (!resume_pending_) return;
  if (arm_ok_since_ns_ == 0) arm_ok_since_ns_ = now_ns;
  // The arm may have braked, drifted or been moved while it was stopped: start from where it is
  // measured after it came back, never from where the controller last aimed.
  if (last_state_ && last_state_->t_ns >= arm_ok_since_ns_ && controller_.resumeFrom(last_state_->q, now_ns)) {
    resume_pending_ = false;
    arm_ok_since_ns_ = 0;
  }
}

std::string HeadLoop::faultLocked() const {
  if (recovery_.running()) return "clearing the fault: re-enabling or reconnecting the arm";
  const arm::ArmStatus status = arm_.status();
  if (status == arm::ArmStatus::kOk) return "";
  // The arm's own cause first, then ours; a stop we asked for is said once, as ours.
  std::string causes;
  const std::string why = arm_.faultText();
  if (!(stopped_by_console_ && why == arm::HeadArm::kStoppedOnRequest)) {
    if (status == arm::ArmStatus::kDisconnected)
      causes = why.empty() ? "arm disconnected" : "arm disconnected: " + why;
    else
      causes = why.empty() ? "arm stopped (fault or emergency stop)" : "arm stopped: " + why;
  }
  if (stopped_by_console_) causes += causes.empty() ? "arm stopped from the console" : "; also stopped from the console";
  return causes;
}

void HeadLoop::fillSettings(link::proto::RobotSettings* settings) const {
  std::lock_guard lock(mutex_);
  settings->set_visual_mode(link::toProto(controller_.mode()));
  settings->set_sphere_radius(sphere_radius_);
  if (depth_proxy_) settings->set_depth_proxy(link::toProto(*depth_proxy_));
  settings->set_filter_cutoff_hz(controller_.config().cutoff_hz);
  settings->set_jump_position_m(controller_.config().jump_position);
  settings->set_jump_angle_deg(controller_.config().jump_angle * 180.0 / M_PI);
}

void HeadLoop::fillHealth(link::proto::RobotHealth* health) const {
  std::lock_guard lock(mutex_);
  for (int r = 1; r < static_cast<int>(HeadRejectReason::kCount); ++r) {
    const auto reason = static_cast<HeadRejectReason>(r);
    if (reason == HeadRejectReason::kMissing || reason == HeadRejectReason::kNotInitialised) continue;
    auto* count = health->add_head_rejects();
    count->set_name(headRejectReasonName(reason));
    count->set_count(static_cast<std::uint64_t>(controller_.rejectionCount(reason)));
  }
  health->set_jumps(static_cast<std::uint64_t>(controller_.jumpCount()));
  health->set_unreachable(static_cast<std::uint64_t>(controller_.unreachableCount()));
  health->set_targets_sent(static_cast<std::uint64_t>(targets_sent_.load()));
  health->set_head_target_age_ns(last_target_ ? clock_.nowNs() - last_target_->sample.t_ns : -1);
  health->set_arm_ok(armOkLocked());
  health->set_fault(faultLocked());
  *health->mutable_hold() = holdLocked();
}

}  // namespace telesphere::robot::head
