// SPDX-License-Identifier: MIT
/// @brief Kinematics of the UFACTORY xArm 6 head arm: forward kinematics with its geometric
///        Jacobian, joint limits, and a joint-limited damped-least-squares inverse kinematics.
///
/// Source of the parameters: the xArm 6 modified (Craig) DH table published by UFACTORY in the
/// xArm user manual ("Kinematic and dynamic parameters of the xArm") and in xarm_ros
/// (xarm_description), cross-checked against public xArm 6 parameter files and a public robotics
/// toolbox model (same d1, a2, offsets, a3, d4, a5, d6 and limits). Per joint i the link transform is
///   T_{i-1}_i = RotX(alpha_{i-1}) · TransX(a_{i-1}) · RotZ(q_i + offset_i) · TransZ(d_i)
/// with (alpha_{i-1} [rad], a_{i-1} [m], d_i [m], offset_i [rad]):
///   J1: (0,     0,       0.267,  0)
///   J2: (−π/2,  0,       0,      −1.3849179)   offset = −atan2(284.5, 53.5)
///   J3: (0,     0.28949, 0,      +1.3849179)   a2 = hypot(284.5, 53.5) mm = 289.48866 mm
///   J4: (−π/2,  0.0775,  0.3425, 0)
///   J5: (+π/2,  0,       0,      0)
///   J6: (−π/2,  0.076,   0.097,  0)
/// At q = 0 the flange is at (0.207, 0, 0.1115) m pointing down (flange z = −robot z), as the
/// xArm 6 reports [207, 0, 112 mm, roll 180°] at its zero pose.
/// Joint limits (xArm 6 manual / xarm_description URDF): J1, J4, J6 ±360°; J2 −118°..120°;
/// J3 −225°..11°; J5 −97°..180°.
///
/// Frames (DESIGN.md §2): `robot` is the arm base (z up), `flange` the tool flange (z out of it).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "robot/arm/joint_state.h"

namespace telesphere::robot::arm {

/// One modified-DH row (see the file comment): alpha_{i-1} [rad], a_{i-1} [m], d_i [m], offset_i.
struct MdhLink {
  double alpha = 0, a = 0, d = 0, theta_offset = 0;
};

/// Inverse-kinematics settings.
struct IkOptions {
  int max_iterations = 100;
  double position_tolerance = 1e-6;  ///< m: converged when both errors are below their tolerance
  double angle_tolerance = 1e-6;     ///< rad
  /// m/rad: how a rotation error trades against a position error in the least-squares cost
  /// |p_err|² + (rotation_weight·|θ_err|)²; it decides what "closest reachable pose" means.
  double rotation_weight = 0.2;
  double min_damping = 1e-4;   ///< λ floor of the damped least squares (units of J: m)
  double max_step = 0.25;      ///< rad: largest change of any joint per iteration
};

/// Outcome of inverse kinematics. `q` is always finite and within the joint limits.
struct IkResult {
  enum class Status {
    kConverged,         ///< the pose was reached within the tolerances
    kClosestReachable,  ///< unreachable (workspace, limits or a singular direction): q is the
                        ///< local optimum of the weighted pose error near the seed
    kInvalidTarget,     ///< NaN/inf or non-rotation target: q is the (clamped) seed
  };
  Status status = Status::kInvalidTarget;
  JointVector q = JointVector::Zero();
  double position_error = 0;  ///< m, |p_target − p(q)|
  double angle_error = 0;     ///< rad, angle of R_target · R(q)ᵀ
  int iterations = 0;
  bool at_joint_limit = false;  ///< some joint of q is on its limit
  bool converged() const { return status == Status::kConverged; }
};

/// 6×6 geometric Jacobian: rows [dp; dθ] in the robot frame, columns J1..J6. A joint change dq
/// moves the flange by dp = J.topRows<3>()·dq and rotates it by R(q + dq) ≈ exp([dθ]×)·R(q) with
/// dθ = J.bottomRows<3>()·dq.
using Jacobian6 = Eigen::Matrix<double, 6, 6>;

class Xarm6Kinematics {
 public:
  static constexpr int kDof = 6;

  /// The published xArm 6 parameters and limits (file comment).
  Xarm6Kinematics();

  const std::array<MdhLink, kDof>& links() const { return links_; }
  /// Joint limits in rad.
  const JointVector& lowerLimits() const { return lower_; }
  const JointVector& upperLimits() const { return upper_; }

  /// True iff every q_i is finite and lower_i − tol ≤ q_i ≤ upper_i + tol.
  bool withinLimits(const JointVector& q, double tol = 0.0) const;
  /// q with each joint clamped into its limits (NaN joints become the midpoint of the range).
  JointVector clampToLimits(const JointVector& q) const;

  /// T_robot_flange(q): forward kinematics, q in rad (any finite value; limits not enforced).
  /// Optionally the geometric Jacobian (Jacobian6).
  Eigen::Isometry3d forward(const JointVector& q, Jacobian6* d_pose_d_q = nullptr) const;

  /// Smallest singular value of the Jacobian with its rotation rows scaled by `rotation_weight`
  /// (m/rad): 0 at a singularity (wrist: J5 = 0; elbow: arm stretched; shoulder: wrist centre on
  /// the J1 axis).
  double minSingularValue(const JointVector& q, double rotation_weight = 0.2) const;

  /// Inverse kinematics for the flange target T_robot_flange_target, starting from q_seed (the
  /// current configuration; it selects the branch, so the answer stays continuous along a path).
  /// Projected Levenberg–Marquardt damped least squares on the weighted pose error: every
  /// iterate is clamped into the joint limits, steps are capped at options.max_step, the damping
  /// grows where a step does not reduce the error (singularities, unreachable targets), so the
  /// result degrades to the closest reachable pose and is flagged (IkResult::Status).
  IkResult inverse(const Eigen::Isometry3d& T_robot_flange_target, const JointVector& q_seed,
                   const IkOptions& options = {}) const;

 private:
  std::array<MdhLink, kDof> links_;
  JointVector lower_, upper_;
};

/// Rotation vector (axis·angle, rad) of a rotation matrix: log map, defined for every rotation.
Eigen::Vector3d rotationLog(const Eigen::Matrix3d& R);

/// True iff R is finite, RᵀR = I within tol and det R > 0.
bool isRotation(const Eigen::Matrix3d& R, double tol = 1e-6);

}  // namespace telesphere::robot::arm
