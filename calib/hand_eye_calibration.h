// SPDX-License-Identifier: MIT
/// @brief Hand-eye calibration of the head arm, the cameras and the manipulator (paper eqs. 1–3,
///        DESIGN.md §2, §6) with the ArUco marker on the manipulator's wrist.
///
/// Model, per sample i and marker corner c (marker frame: OpenCV's, corners at (∓s/2, ±s/2, 0)):
///   p_cam_l = T_flange_cam_l⁻¹ · T_robot_flange(i)⁻¹ · T_robot_mount · T_mount_wrist(i)
///             · T_wrist_marker · p_marker(c),          p_cam_r = T_cam_l_cam_r⁻¹ · p_cam_l,
/// residuals f_l(p_cam_l) − px_l and f_r(p_cam_r) − px_r under a Huber loss, minimised by Ceres
/// over T_flange_cam_l, T_robot_mount and T_wrist_marker with the intrinsics and T_cam_l_cam_r
/// fixed. T_robot_flange and T_mount_wrist come from the forward kinematics of the two arms
/// (computed by the caller: calib does not depend on robot/).
///
/// Initialisation in closed form (from 10 samples; below that from a given T_flange_cam_l, see
/// HandEyeOptions::T_flange_cam_l_guess): per sample the marker pose T_cam_l_marker from bearings; then
/// F·X·M = Z·W·Y (X = T_flange_cam_l, Z = T_robot_mount, Y = T_wrist_marker) is solved for the
/// rotations linearly through the Kronecker product (R_Mᵀ ⊗ R_F)·vec(R_X) =
/// (vec(R_W)ᵀ ⊗ I₉)·vec(R_Yᵀ ⊗ R_Z) and the rank-1 factorisation of R_Yᵀ ⊗ R_Z, then the
/// translations by linear least squares (the AXB = YCZ form of robot-world-hand-eye
/// calibration; OpenCV's calibrateRobotWorldHandEye solves the two-unknown special case).
///
/// Identifiability: the unknowns separate only when the head flange rotates about at least two
/// non-parallel axes and so does the manipulator's wrist; otherwise the solve is refused with
/// CalibrationError::kNotIdentifiable instead of returning a confident wrong answer.
/// One concept: one Ceres problem (paper eqs. 1–3, about 500 lines) with its initialisation from
/// the samples and the result's figures.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calib/calibration_failure.h"
#include "calib/pose_stddev.h"
#include "calib/system_calibration.h"

namespace telesphere::calib {

struct HandEyeSample {
  std::int64_t t_ns = 0;                 ///< capture time of the image pair
  Eigen::Isometry3d T_robot_flange = Eigen::Isometry3d::Identity();  ///< head arm FK
  Eigen::Isometry3d T_mount_wrist = Eigen::Isometry3d::Identity();   ///< manipulator FK
  /// Marker corners (OpenCV order) in cam_l and cam_r, px; absent where the marker was not seen.
  std::optional<std::array<Eigen::Vector2d, 4>> corners_l;
  std::optional<std::array<Eigen::Vector2d, 4>> corners_r;
};

struct HandEyeOptions {
  double huber_px = 1.0;
  int max_iterations = 100;
  int min_samples = 8;               ///< samples with the marker seen in at least one camera
  double min_axis_spread_deg = 10.0; ///< see HandEyeIdentifiability
  double min_rotation_deg = 3.0;     ///< relative rotations below this carry no axis
  double max_rms_px = 5.0;           ///< a median sample RMS above this means the solve diverged
  std::function<void(const std::string&)> progress;
  /// A starting T_flange_cam_l (e.g. the calibration the robot runs with): X from here, Z and Y
  /// from the marker poses it implies. The only start below kClosedFormMinSamples samples (the
  /// closed form is not unique there); from there on a second start beside the closed form,
  /// which with few or noisy samples can lead into a wrong minimum.
  std::optional<Eigen::Isometry3d> T_flange_cam_l_guess;
};

/// The closed form's Kronecker system has 90 unknowns and 9 equations per sample.
inline constexpr int kClosedFormMinSamples = 10;

/// How well the samples separate the unknowns: the spread of the rotation axes of the relative
/// rotations between samples, atan(√(λ₂/λ₁)) of the axes' scatter matrix (0° when all axes are
/// parallel, 45° for two perpendicular axes used alike).
struct HandEyeIdentifiability {
  double head_axis_spread_deg = 0;
  double wrist_axis_spread_deg = 0;
  int samples = 0;
  bool ok = false;
  std::string message;  ///< why not, for the user
};

HandEyeIdentifiability checkHandEyeIdentifiability(const std::vector<HandEyeSample>& samples,
                                                   const HandEyeOptions& options = {});

/// One input sample's fit after the solve.
struct HandEyeSampleFit {
  std::size_t index = 0;  ///< in the samples given to calibrateHandEye
  double rms_px = 0;      ///< over its marker corners in both cameras
  int corners = 0;
};

struct HandEyeResult {
  Eigen::Isometry3d T_flange_cam_l = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_robot_mount = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_wrist_marker = Eigen::Isometry3d::Identity();
  /// The start the result was refined from (before Ceres), same order: the closed form, or the
  /// one from HandEyeOptions::T_flange_cam_l_guess when that fitted better.
  std::array<Eigen::Isometry3d, 3> initial;
  double rms_px_l = 0, rms_px_r = 0;  ///< final reprojection RMS per camera (0 when unused)
  int samples_used = 0;
  double initial_cost = 0, final_cost = 0;
  HandEyeIdentifiability identifiability;
  /// Standard deviations of T_flange_cam_l, T_robot_mount, T_wrist_marker (same order as initial).
  std::array<PoseStddev, 3> stddev;
  /// Every sample used, in input order: its residual after the solve.
  std::vector<HandEyeSampleFit> sample_fits;
};

/// Calibrates from `samples` with the cameras and T_cam_l_cam_r of `cameras` (one or two
/// cameras) and a marker of edge `marker_size` metres.
SolveResult<HandEyeResult> calibrateHandEye(const SystemCalibration& cameras, double marker_size,
                                            const std::vector<HandEyeSample>& samples,
                                            const HandEyeOptions& options = {});

/// The marker's corners in the marker frame (OpenCV order), metres.
std::array<Eigen::Vector3d, 4> markerCorners(double marker_size);

}  // namespace telesphere::calib
