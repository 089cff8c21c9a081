// SPDX-License-Identifier: MIT
/// @brief HeadController (see head_controller.h).
#include "robot/head/head_controller.h"

#include <algorithm>
#include <cmath>

#include "calib/debug_assert.h"
#include "robot/link/head_angles.h"

namespace telesphere::robot::head {
namespace {

double angleBetween(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b) {
  return arm::rotationLog(R_a * R_b.transpose()).norm();
}

Eigen::Quaterniond quaternionOf(const Eigen::Matrix3d& R) {
  return Eigen::Quaterniond(R).normalized();
}

/// Moves `from` towards `to` by at most max_distance (m) and max_angle (rad).
Eigen::Isometry3d stepTowards(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to,
                              double max_distance, double max_angle) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d dp = to.translation() - from.translation();
  const double distance = dp.norm();
  out.translation() = distance <= max_distance ? to.translation()
                                               : Eigen::Vector3d(from.translation() +
                                                                 dp * (max_distance / distance));
  const double angle = angleBetween(to.linear(), from.linear());
  const double fraction = angle <= max_angle ? 1.0 : max_angle / angle;
  out.linear() = quaternionOf(from.linear())
                     .slerp(fraction, quaternionOf(to.linear()))
                     .normalized()
                     .toRotationMatrix();
  return out;
}

}  // namespace

const char* headRejectReasonName(HeadRejectReason reason) {
  switch (reason) {
    case HeadRejectReason::kNone: return "none";
    case HeadRejectReason::kNotInitialised: return "not_initialised";
    case HeadRejectReason::kMissing: return "missing";
    case HeadRejectReason::kNonFinite: return "non_finite";
    case HeadRejectReason::kNotRotation: return "not_rotation";
    case HeadRejectReason::kStale: return "stale";
    case HeadRejectReason::kFromFuture: return "from_future";
    case HeadRejectReason::kOutOfOrder: return "out_of_order";
    case HeadRejectReason::kCount: break;
  }
  return "unknown";
}

Eigen::Isometry3d HeadControllerConfig::defaultNominal() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.40, 0.0, 0.45);
  return T;
}

Eigen::AlignedBox3d HeadControllerConfig::defaultWorkspace() {
  const Eigen::Vector3d centre = defaultNominal().translation();
  const Eigen::Vector3d half(0.20, 0.30, 0.20);
  return Eigen::AlignedBox3d(centre - half, centre + half);
}

arm::IkOptions HeadControllerConfig::defaultIk() {
  arm::IkOptions options;
  options.max_iterations = 30;  // seeded with the last target, 1–4 iterations are typical
  options.position_tolerance = 1e-5;
  options.angle_tolerance = 1e-4;
  return options;
}

HeadController::HeadController(const HeadControllerConfig& config)
    : config_(config),
      T_flange_head_(config.geometry.T_flange_head()),
      T_head_flange_(T_flange_head_.inverse()),
      filter_(config.cutoff_hz) {
  TS_ASSERT(config.jump_position > 0 && config.jump_angle > 0 && config.approach_speed > 0 &&
                config.approach_angular_speed > 0 && config.caught_up_position > 0 &&
                config.caught_up_angle > 0 && !config.workspace.isEmpty() &&
                config.max_sample_age_ns > 0 && config.max_sample_lead_ns >= 0,
            config.jump_position, config.jump_angle, config.approach_speed,
            config.approach_angular_speed, config.max_sample_age_ns);
  TS_ASSERT(arm::isRotation(config.T_robot_nom.linear()), config.T_robot_nom.matrix());
}

Eigen::Isometry3d HeadController::T_hmd_head() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = Eigen::Vector3d(0, 0, -1);  // head x (forward) = −z of the OpenXR view
  T.linear().col(1) = Eigen::Vector3d(-1, 0, 0);  // head y (left) = −x (x points right)
  T.linear().col(2) = Eigen::Vector3d(0, 1, 0);   // head z (up) = y
  return T;
}

bool HeadController::initialise(const HmdSample& nominal, const arm::JointVector& q_current) {
  if (!nominal.T_vr_hmd.matrix().allFinite() || !arm::isRotation(nominal.T_vr_hmd.linear(), 1e-3) ||
      !q_current.allFinite())
    return false;
  T_robot_vr_ = mappingFor(nominal.T_vr_hmd);
  startFrom(q_current, nominal.t_ns);
  filter_.reset(mapped(nominal.T_vr_hmd), nominal.t_ns);
  last_sample_t_ns_ = nominal.t_ns;
  initialised_ = true;
  return true;
}

void HeadController::startFrom(const arm::JointVector& q_measured, std::int64_t now_ns) {
  q_last_ = kinematics_.clampToLimits(q_measured);
  guarded_ = kinematics_.forward(q_last_) * T_flange_head_;
  last_tick_ns_ = now_ns;  // the first step is one period's, not the time since the last tick
  // At the approach speeds, however near the target: a step below the jump guard's thresholds
  // would otherwise be sent in one tick (8° of J2 in 10 ms on an xArm, whose driver refuses it).
  approaching_ = true;
}

Eigen::Isometry3d HeadController::mappingFor(const Eigen::Isometry3d& T_vr_hmd) const {
  const Eigen::Isometry3d T_vr_nom = link::withoutPitchAndRoll(T_vr_hmd) * T_hmd_head();
  return config_.T_robot_nom * T_vr_nom.inverse();
}

bool HeadController::holdNominal(const arm::JointVector& q_current, std::int64_t now_ns) {
  return holdAt(config_.T_robot_nom, q_current, now_ns);
}

bool HeadController::holdAt(const Eigen::Isometry3d& T_robot_head, const arm::JointVector& q_current, std::int64_t now_ns) {
  if (!q_current.allFinite() || !T_robot_head.matrix().allFinite() || !arm::isRotation(T_robot_head.linear(), 1e-3)) {
    return false;
  }
  hold_target_ = T_robot_head;
  if (!initialised_) {
    // No operator target has been followed yet: the approach starts where the arm is.
    startFrom(q_current, now_ns);
    filter_.reset(guarded_, now_ns);
  }
  holding_ = true;
  return true;
}

arm::IkResult HeadController::reachAlongApproach(const Eigen::Isometry3d& T_robot_head, const arm::JointVector& q_from) const {
  arm::IkResult ik;
  ik.q = kinematics_.clampToLimits(q_from);
  if (!q_from.allFinite() || !T_robot_head.matrix().allFinite() || !arm::isRotation(T_robot_head.linear(), 1e-3)) return ik;
  const Eigen::Isometry3d T_start = kinematics_.forward(ik.q) * T_flange_head_;
  const double distance = (T_robot_head.translation() - T_start.translation()).norm();
  const double angle = angleBetween(T_robot_head.linear(), T_start.linear());
  const int steps = std::max(1, int(std::ceil(std::max(distance / kPathStep, angle / kPathStepAngle))));
  Eigen::Isometry3d T_step = T_start;
  for (int i = 1; i <= steps; ++i) {
    // As the approach steps each tick (its speeds times the tick), the last step onto the pose itself.
    T_step = i == steps ? T_robot_head : stepTowards(T_step, T_robot_head, kPathStep, kPathStepAngle);
    ik = kinematics_.inverse(T_step * T_head_flange_, ik.q, config_.ik);
    if (ik.status == arm::IkResult::Status::kInvalidTarget) return ik;
  }
  return ik;
}

bool HeadController::resumeFrom(const arm::JointVector& q_measured, std::int64_t now_ns) {
  if (!q_measured.allFinite()) return false;
  startFrom(q_measured, now_ns);
  ++resumes_;
  return true;
}

bool HeadController::moveHold(const Eigen::Isometry3d& T_robot_head) {
  if (!holding_ || !T_robot_head.matrix().allFinite() || !arm::isRotation(T_robot_head.linear(), 1e-3)) return false;
  hold_target_ = T_robot_head;
  return true;
}

void HeadController::restoreMapping(const Eigen::Isometry3d& T_robot_vr) {
  TS_ASSERT(initialised_ && arm::isRotation(T_robot_vr.linear(), 1e-6), T_robot_vr.matrix());
  T_robot_vr_ = T_robot_vr;
}

void HeadController::setGeometry(const HeadGeometry& geometry) {
  config_.geometry = geometry;
  T_flange_head_ = geometry.T_flange_head();
  T_head_flange_ = T_flange_head_.inverse();
  if (initialised_ || holding_) guarded_ = kinematics_.forward(q_last_) * T_flange_head_;
}

void HeadController::setCutoffHz(double cutoff_hz) {
  TS_ASSERT(cutoff_hz > 0, cutoff_hz);
  config_.cutoff_hz = cutoff_hz;
  filter_.setCutoffHz(cutoff_hz);
}

void HeadController::setJumpThreshold(double position, double angle) {
  TS_ASSERT(position > 0 && angle > 0, position, angle);
  config_.jump_position = position;
  config_.jump_angle = angle;
}

Eigen::Isometry3d HeadController::mapped(const Eigen::Isometry3d& T_vr_hmd) const {
  Eigen::Isometry3d T = T_robot_vr_ * T_vr_hmd * T_hmd_head();
  T.linear() = quaternionOf(T.linear()).toRotationMatrix();  // float input: re-orthonormalise
  return T;
}

HeadRejectReason HeadController::validate(const std::optional<HmdSample>& sample,
                                          std::int64_t now_ns) const {
  if (!sample) return HeadRejectReason::kMissing;
  if (!sample->T_vr_hmd.matrix().allFinite()) return HeadRejectReason::kNonFinite;
  if (!arm::isRotation(sample->T_vr_hmd.linear(), 1e-3)) return HeadRejectReason::kNotRotation;
  if (sample->t_ns > now_ns + config_.max_sample_lead_ns) return HeadRejectReason::kFromFuture;
  if (now_ns - sample->t_ns > config_.max_sample_age_ns) return HeadRejectReason::kStale;
  if (sample->t_ns < last_sample_t_ns_) return HeadRejectReason::kOutOfOrder;
  return HeadRejectReason::kNone;
}

HeadCommand HeadController::hold(HeadRejectReason reason) {
  ++rejections_[static_cast<std::size_t>(reason)];
  HeadCommand cmd;
  cmd.send = false;
  cmd.q_target = q_last_;
  cmd.reason = reason;
  cmd.approaching = approaching_;
  cmd.T_robot_headTarget = kinematics_.forward(q_last_) * T_flange_head_;
  return cmd;
}

HeadCommand HeadController::tick(const std::optional<HmdSample>& sample, std::int64_t now_ns) {
  if (!initialised_ && !holding_) return hold(HeadRejectReason::kNotInitialised);
  const double dt = static_cast<double>(std::max<std::int64_t>(0, now_ns - last_tick_ns_)) * 1e-9;

  Eigen::Isometry3d target;
  std::int64_t target_t_ns = now_ns;
  if (holding_) {
    target = hold_target_;  // the nominal-pose step or a calibration pose: the operator is ignored
  } else if (mode_ == link::VisualMode::kFixed) {
    // Operator ignored: the nominal pose pitched 45° down (about the head's y axis, left).
    target = config_.T_robot_nom * Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY());
  } else {
    const HeadRejectReason reason = validate(sample, now_ns);
    if (reason != HeadRejectReason::kNone) {
      last_tick_ns_ = now_ns;
      return hold(reason);
    }
    target = mapped(sample->T_vr_hmd);
    if (mode_ == link::VisualMode::kOrientation3d) target.translation() = config_.T_robot_nom.translation();
    target_t_ns = sample->t_ns;
    last_sample_t_ns_ = sample->t_ns;
  }
  last_tick_ns_ = now_ns;
  const Eigen::Isometry3d filtered = filter_.update(target, target_t_ns);

  // Workspace clamp of what is wanted, before the jump guard: an arm standing outside the box
  // (moved there by hand, or at start-up) is brought in at the approach speeds, not in one tick.
  HeadCommand cmd;
  Eigen::Isometry3d wanted = filtered;
  const Eigen::Vector3d p = filtered.translation();
  wanted.translation() = p.cwiseMax(config_.workspace.min()).cwiseMin(config_.workspace.max());
  cmd.clamped = (wanted.translation() - p).norm() > 0;

  // Jump guard.
  double dp = (wanted.translation() - guarded_.translation()).norm();
  double da = angleBetween(wanted.linear(), guarded_.linear());
  if (!approaching_ && (dp > config_.jump_position || da > config_.jump_angle)) {
    approaching_ = true;
    ++jumps_;
  }
  if (approaching_) {
    guarded_ = stepTowards(guarded_, wanted, config_.approach_speed * dt,
                           config_.approach_angular_speed * dt);
    dp = (wanted.translation() - guarded_.translation()).norm();
    da = angleBetween(wanted.linear(), guarded_.linear());
    if (dp <= config_.caught_up_position && da <= config_.caught_up_angle) approaching_ = false;
  } else {
    guarded_ = wanted;
  }
  cmd.approaching = approaching_;
  const Eigen::Isometry3d T_robot_head = guarded_;

  // Inverse kinematics, seeded with the last target.
  const arm::IkResult ik = kinematics_.inverse(T_robot_head * T_head_flange_, q_last_, config_.ik);
  if (ik.status == arm::IkResult::Status::kInvalidTarget) return hold(HeadRejectReason::kNonFinite);
  if (ik.status == arm::IkResult::Status::kClosestReachable) ++unreachable_;
  TS_ASSERT(kinematics_.withinLimits(ik.q), ik.q.transpose());
  q_last_ = ik.q;
  cmd.send = true;
  cmd.q_target = q_last_;
  cmd.ik_status = ik.status;
  cmd.T_robot_headTarget = T_robot_head;
  return cmd;
}

}  // namespace telesphere::robot::head
