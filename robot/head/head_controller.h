// SPDX-License-Identifier: MIT
/// @brief HeadController: operator head pose → head-arm joint target, once per 100 Hz tick
///        (paper §III-C, DESIGN.md §2 and §5).
///
/// Pipeline per tick:
///   1. validate the HMD sample (finite, a rotation, timestamp fresh and in order) — a bad one is
///      rejected with a counted reason and the arm holds its last target;
///   2. map: T_robot_headTarget = T_robot_nom · T_vr_nom⁻¹ · T_vr_hmd · T_hmd_head, where T_vr_nom
///      is the (head-axis) HMD pose recorded at initialise() with pitch and roll removed, and
///      T_hmd_head the constant axis change below; per mode: full 6D; orientation only (position
///      held at the nominal one); fixed (T_robot_nom pitched 45° down, the operator ignored);
///      while holdNominal() is on, T_robot_nom itself (the operator ignored, any mode, also
///      before the first initialise: the console's nominal-pose step), and while holdAt() is on
///      the pose it was given (the calibration wizards);
///   3. recursive low-pass filter (PoseLowPassFilter, cut-off a parameter, paper 100 Hz) on the
///      sample times;
///   4. workspace clamp of the head position to an axis-aligned box in the robot frame;
///   5. jump guard: a change beyond jump_position or jump_angle from the last output switches to
///      a slow approach at approach_speed / approach_angular_speed until within the caught-up
///      tolerances (after the clamp, so an arm standing outside the box is brought in slowly);
///   6. inverse kinematics of T_robot_flange = T_robot_head · T_head_flange, seeded with the last
///      target (continuity); the result is inside the joint limits by construction.
///
/// Axis convention (STYLE.md §6, §11): T_vr_hmd is the OpenXR view pose (x right, y up, −z
/// forward) in a reference space whose +y is up; the robot `head` frame is x forward, y left,
/// z up. T_hmd_head() is the one named constant between them, so that a relative operator motion
/// expressed in head axes is applied to T_robot_nom in head axes.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "robot/head/head_geometry.h"
#include "robot/arm/joint_state.h"
#include "robot/link/visual_mode.h"
#include "robot/head/low_pass_filter.h"
#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot::head {


/// Why a tick did not produce a new target.
enum class HeadRejectReason {
  kNone = 0,        ///< accepted
  kNotInitialised,  ///< initialise() has not succeeded yet
  kMissing,         ///< no sample this tick
  kNonFinite,       ///< NaN or inf in the pose
  kNotRotation,     ///< rotation part not orthonormal with det +1 (tolerance 1e-3, float input)
  kStale,           ///< older than max_sample_age_ns at the tick
  kFromFuture,      ///< newer than the tick by more than max_sample_lead_ns
  kOutOfOrder,      ///< older than the last accepted sample
  kCount
};

/// "not_initialised", "missing", "non_finite", … (health reports and logs).
const char* headRejectReasonName(HeadRejectReason reason);

/// One operator head sample: the OpenXR view pose T_vr_hmd observed at t_ns (robot steady clock).
struct HmdSample {
  std::int64_t t_ns = 0;
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
};

struct HeadControllerConfig {
  /// The nominal robot head pose (robot frame): the head looks straight ahead (+x of the robot).
  Eigen::Isometry3d T_robot_nom = defaultNominal();
  HeadGeometry geometry = HeadGeometry::example();
  double cutoff_hz = 100.0;                  ///< low-pass cut-off (paper: 100 Hz); inf: off
  double jump_position = 0.10;               ///< m: a larger target change is a jump
  double jump_angle = 20.0 * M_PI / 180.0;   ///< rad
  double approach_speed = 0.15;              ///< m/s during the slow approach
  double approach_angular_speed = 45.0 * M_PI / 180.0;  ///< rad/s during the slow approach
  double caught_up_position = 0.002;         ///< m: the approach ends within these
  double caught_up_angle = 0.5 * M_PI / 180.0;  ///< rad
  /// Head positions allowed, robot frame (m); the default is the nominal ± (0.20, 0.30, 0.20).
  Eigen::AlignedBox3d workspace = defaultWorkspace();
  std::int64_t max_sample_age_ns = 100'000'000;  ///< older samples are stale
  std::int64_t max_sample_lead_ns = 5'000'000;   ///< tolerated clock skew of newer samples
  arm::IkOptions ik = defaultIk();

  /// The default nominal head pose: 0.40 m in front of the base, 0.45 m up, looking along +x.
  static Eigen::Isometry3d defaultNominal();
  static Eigen::AlignedBox3d defaultWorkspace();
  static arm::IkOptions defaultIk();
};

/// What one tick produced.
struct HeadCommand {
  bool send = false;  ///< true: q_target is new and should be sent; false: hold (keep the last)
  arm::JointVector q_target = arm::JointVector::Zero();  ///< last or new target, always within limits
  HeadRejectReason reason = HeadRejectReason::kNone;
  bool approaching = false;     ///< the jump guard's slow approach is active
  bool clamped = false;         ///< the workspace clamp moved the target
  arm::IkResult::Status ik_status = arm::IkResult::Status::kConverged;
  Eigen::Isometry3d T_robot_headTarget = Eigen::Isometry3d::Identity();  ///< what IK aimed at
};

class HeadController {
 public:
  explicit HeadController(const HeadControllerConfig& config = {});

  /// OpenXR view axes → head axes: columns are head x, y, z in the OpenXR view frame.
  static Eigen::Isometry3d T_hmd_head();

  /// Starts the mapping with the operator looking straight ahead (`nominal`) and the arm at
  /// q_current: the output starts from the current head pose and approaches the target at the
  /// approach speeds until caught up, however near it is. False (nothing changes) if the sample
  /// is invalid.
  bool initialise(const HmdSample& nominal, const arm::JointVector& q_current);
  /// The mapping initialise() would set for this head pose: T_robot_nom · (withoutPitchAndRoll(T_vr_hmd) ·
  /// T_hmd_head)⁻¹ (the console shows it before it is confirmed).
  Eigen::Isometry3d mappingFor(const Eigen::Isometry3d& T_vr_hmd) const;
  bool initialised() const { return initialised_; }

  void setMode(link::VisualMode mode) { mode_ = mode; }
  link::VisualMode mode() const { return mode_; }

  /// Moves the head to T_robot_nom (through the jump guard's slow approach) and holds it there,
  /// the operator ignored, until releaseHold(). Without a mapping yet, the output starts from
  /// the arm's q_current at now_ns and approaches at the approach speeds however near the pose
  /// is. False (nothing changes) for non-finite joints.
  bool holdNominal(const arm::JointVector& q_current, std::int64_t now_ns);
  /// The same hold at any head pose T_robot_head (the calibration wizards' head poses): false
  /// (nothing changes) for non-finite joints or a pose that is not a rigid transform.
  bool holdAt(const Eigen::Isometry3d& T_robot_head, const arm::JointVector& q_current, std::int64_t now_ns);
  void releaseHold() { holding_ = false; }
  /// Whether the arm, standing at q_from, reaches the head pose T_robot_head the way a hold takes
  /// it there: the head pose of q_from stepped towards T_robot_head by at most kPathStep (m) and
  /// kPathStepAngle (rad) at a time, each step's IK seeded with the step before's joints, as
  /// tick() seeds each tick's with the last. Returns the last step's IK (converged: reachable
  /// along the way). One IK from q_from alone can stop short of a pose the arm reaches (a
  /// calibration pose 90° away from the head's last one), or reach it by another arm
  /// configuration than the approach ends in.
  arm::IkResult reachAlongApproach(const Eigen::Isometry3d& T_robot_head, const arm::JointVector& q_from) const;
  /// The approach's step in one 10 ms tick at its default speeds (0.15 m/s, 45°/s): with 1 cm / 2°
  /// steps one pose of 3689 that a single IK reached stalled on the way.
  static constexpr double kPathStep = 0.0015;
  static constexpr double kPathStepAngle = 0.45 * M_PI / 180.0;
  /// Moves the pose held (a calibration pattern, every tick); false (nothing changes) when not
  /// holding or for a pose that is not a rigid transform.
  bool moveHold(const Eigen::Isometry3d& T_robot_head);
  bool holding() const { return holding_; }

  /// After the arm stood still for a while (a stop, a fault, a reconnect): the output starts again
  /// from the measured joints q_measured at now_ns, and whatever the target is by then (the
  /// operator kept moving, a hold moved on) is approached at approach_speed and
  /// approach_angular_speed, however small the difference (a jump below the threshold would still
  /// be a step the arm takes at full speed). False (nothing changes) for non-finite joints.
  bool resumeFrom(const arm::JointVector& q_measured, std::int64_t now_ns);
  std::int64_t resumeCount() const { return resumes_; }

  /// Restores a mapping T_robot_vr taken from an earlier initialise() (undo); needs one.
  void restoreMapping(const Eigen::Isometry3d& T_robot_vr);

  /// A new camera mount (a calibration applied live), from the next tick on: the head frame is
  /// the new one. The arm has not moved, so the guard starts from where the new head frame is
  /// now, and a change beyond the jump thresholds is approached slowly like any jump.
  void setGeometry(const HeadGeometry& geometry);

  /// Low-pass cut-off (> 0; +inf: off) and jump thresholds (> 0), from the next tick on.
  void setCutoffHz(double cutoff_hz);
  void setJumpThreshold(double position, double angle);

  /// One control tick at now_ns with the newest operator sample (if any).
  HeadCommand tick(const std::optional<HmdSample>& sample, std::int64_t now_ns);

  /// T_robot_vr = T_robot_nom · T_vr_nom⁻¹ (head axes): takes any vr pose in head axes, e.g. an
  /// eye pose T_vr_eye · T_hmd_head, into the robot frame (DESIGN.md §2).
  const Eigen::Isometry3d& T_robot_vr() const { return T_robot_vr_; }

  std::int64_t rejectionCount(HeadRejectReason reason) const {
    return rejections_[static_cast<std::size_t>(reason)];
  }
  std::int64_t jumpCount() const { return jumps_; }
  std::int64_t unreachableCount() const { return unreachable_; }
  const HeadControllerConfig& config() const { return config_; }
  const arm::Xarm6Kinematics& kinematics() const { return kinematics_; }

 private:
  /// The output starts at the head pose of the measured joints (clamped to the limits) and
  /// approaches its target at the approach speeds until caught up: initialise, a hold before
  /// any operator target, and a resume all start here.
  void startFrom(const arm::JointVector& q_measured, std::int64_t now_ns);
  HeadRejectReason validate(const std::optional<HmdSample>& sample, std::int64_t now_ns) const;
  Eigen::Isometry3d mapped(const Eigen::Isometry3d& T_vr_hmd) const;
  HeadCommand hold(HeadRejectReason reason);

  HeadControllerConfig config_;
  arm::Xarm6Kinematics kinematics_;
  Eigen::Isometry3d T_flange_head_, T_head_flange_;
  Eigen::Isometry3d T_robot_vr_ = Eigen::Isometry3d::Identity();
  PoseLowPassFilter filter_;
  link::VisualMode mode_ = link::VisualMode::kFull6d;
  bool initialised_ = false;
  bool holding_ = false;
  Eigen::Isometry3d hold_target_ = Eigen::Isometry3d::Identity();  ///< while holding_
  bool approaching_ = false;
  Eigen::Isometry3d guarded_ = Eigen::Isometry3d::Identity();  ///< jump-guard output
  Eigen::Isometry3d last_operator_target_ = Eigen::Isometry3d::Identity();
  std::int64_t last_sample_t_ns_ = 0;
  std::int64_t last_tick_ns_ = 0;
  arm::JointVector q_last_ = arm::JointVector::Zero();
  std::array<std::int64_t, static_cast<std::size_t>(HeadRejectReason::kCount)> rejections_{};
  std::int64_t jumps_ = 0, unreachable_ = 0, resumes_ = 0;
};

}  // namespace telesphere::robot::head
