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

namespace telesphere::robot {


HeadLoop::HeadLoop(HeadArm& arm, HeadController& controller, JointStateBuffer& buffer,
                   link::LinkServer& server, const Clock& clock, const HeadLoopConfig& config)
    : arm_(arm),
      controller_(controller),
      buffer_(buffer),
      server_(server),
      clock_(clock),
      config_(config),
      T_flange_head_(controller.config().geometry.T_flange_head()),
      recovery_(arm),
      sphere_radius_(config.sphere_radius) {}

std::optional<JointState> HeadLoop::lastState() const {
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
    t.set_unreachable(command.send && command.ik_status == IkResult::Status::kClosestReachable);
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

bool HeadLoop::armOkLocked() const { return !recovery_.running() && arm_.status() == ArmStatus::kOk; }

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
  if (arm_.status() != ArmStatus::kOk) {
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
  const ArmStatus status = arm_.status();
  if (status == ArmStatus::kOk) return "";
  // The arm's own cause first, then ours; a stop we asked for is said once, as ours.
  std::string causes;
  const std::string why = arm_.faultText();
  if (!(stopped_by_console_ && why == HeadArm::kStoppedOnRequest)) {
    if (status == ArmStatus::kDisconnected)
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
  const IkResult ik = controller_.kinematics().inverse(T_robot_head * T_flange_head_.inverse(), last_state_->q,
                                                       controller_.config().ik);
  if (ik.status != IkResult::Status::kConverged) {
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
            IkResult::Status::kConverged) {
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

link::proto::ControlReply HeadLoop::handleControl(const link::proto::ControlRequest& request) {
  link::proto::ControlReply reply;
  reply.set_id(request.id());
  std::string error;
  bool ok = true;
  bool nominal = false;
  {
    std::lock_guard lock(mutex_);
    switch (request.request_case()) {
      case link::proto::ControlRequest::kSetVisualMode:
        if (const auto mode = link::fromProto(request.set_visual_mode())) {
          controller_.setMode(*mode);
        } else {
          ok = false;
          error = "unknown visual mode " + std::to_string(request.set_visual_mode()) +
                  " (full6d, orientation3d or fixed)";
        }
        break;
      case link::proto::ControlRequest::kCaptureNominal:
        nominal = true;
        if (!last_target_) {
          ok = false;
          error = "no head target received yet: put the headset on and try again";
        } else {
          pending_nominal_ = true;  // taken by the next tick, which has the newest joint state
        }
        break;
      case link::proto::ControlRequest::kNominalStep:
        nominal = true;
        ok = nominalStepLocked(request.nominal_step(), &error);
        break;
      case link::proto::ControlRequest::kSetSphereRadius: {
        const double r = request.set_sphere_radius();
        if (!link::acceptedSphereRadius(r)) {
          ok = false;
          error = "sphere radius " + std::to_string(r) + " m is outside [" +
                  std::to_string(link::kMinSphereRadius) + ", " + std::to_string(link::kMaxSphereRadius) + "]";
        } else {
          sphere_radius_ = r;
        }
        break;
      }
      case link::proto::ControlRequest::kSetFilterCutoffHz: {
        const double f = request.set_filter_cutoff_hz();
        if (!(f > 0.0) || std::isnan(f)) {  // +inf is allowed: the filter is off
          ok = false;
          error = "filter cut-off " + std::to_string(f) + " Hz must be > 0 (inf: off)";
        } else {
          controller_.setCutoffHz(f);
        }
        break;
      }
      case link::proto::ControlRequest::kSetJumpThreshold: {
        const double p = request.set_jump_threshold().position_m();
        const double a = request.set_jump_threshold().angle_deg();
        if (!(std::isfinite(p) && p > 0.0 && p <= 2.0 && std::isfinite(a) && a > 0.0 && a <= 180.0)) {
          ok = false;
          error = "jump threshold " + std::to_string(p) + " m / " + std::to_string(a) +
                  "° is outside (0, 2] m / (0, 180]°";
        } else {
          controller_.setJumpThreshold(p, a * M_PI / 180.0);
        }
        break;
      }
      case link::proto::ControlRequest::kArmStop:
        stopped_by_console_ = true;
        if (recovery_.running())
          stop_after_recovery_ = true;  // the recovery owns the arm; the stop follows it at once
        else
          arm_.stop();
        std::cerr << "telesphere-robot: arm stopped from the console\n";
        break;
      case link::proto::ControlRequest::kClearFault:
        // Answered at once: the recovery runs on its own thread and the state shows its outcome.
        followArmLocked(clock_.nowNs());  // the outcome of an earlier recovery, if not taken yet
        if (armOkLocked()) break;         // nothing to clear
        if (recovery_.running() || recovery_.start()) {
          reply.set_pending(true);
          std::cerr << "telesphere-robot: clearing the arm's fault\n";
        }
        break;
      case link::proto::ControlRequest::kGetSettings:
        break;
      case link::proto::ControlRequest::kSetTrialIndicator: {
        const auto& t = request.set_trial_indicator();
        if (!(std::isfinite(t.elapsed_s()) && t.elapsed_s() >= 0.0 && std::isfinite(t.time_limit_s()) &&
              t.time_limit_s() >= 0.0)) {
          ok = false;
          error = "trial indicator: elapsed and time limit must be finite and ≥ 0 s";
        } else {
          trial_ = t;
          trial_received_ns_ = clock_.nowNs();
        }
        break;
      }
      case link::proto::ControlRequest::kCalibrationHeadPose:
        ok = calibrationHoldLocked(request.calibration_head_pose(), &error);
        *reply.mutable_hold() = holdLocked();
        break;
      case link::proto::ControlRequest::kCalibrationCapture:
        ok = false;
        error = "calibration stills come from the video path, not the head loop";
        break;
      case link::proto::ControlRequest::kSetJpegQuality:
        ok = false;
        error = "JPEG settings belong to the video path, not the head loop";
        break;
      default:
        ok = false;
        error = "empty control request";
    }
    if (nominal) *reply.mutable_nominal() = nominalMappingLocked();
  }
  reply.set_ok(ok);
  reply.set_error(error);
  fillSettings(reply.mutable_settings());
  return reply;
}

}  // namespace telesphere::robot
