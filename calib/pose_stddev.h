// SPDX-License-Identifier: MIT
/// @brief A solved pose's standard deviations from its solve's covariance (hand-eye transforms,
///        the stereo extrinsic T_cam_l_cam_r).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace telesphere::calib {

/// A pose's standard deviations from the solve's covariance (scaled by the residuals' variance):
/// translation per axis in the pose's parent frame, rotation per axis of the perturbation
/// exp([δ]×)·R (also in the parent frame), deg. Not valid when the covariance could not be computed (rank deficient).
struct PoseStddev {
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_deg = Eigen::Vector3d::Zero();
  bool valid = false;
};

/// A pose's covariance, ordered (θ, t): θ the rotation vector of the perturbation exp([θ]×)·R and
/// t the translation, both in the pose's parent frame (rad, m).
using PoseCovariance = Eigen::Matrix<double, 6, 6>;

/// The covariance of T_b_a = T_a_b⁻¹ from that of T_a_b, to first order: R_b_a = R_a_bᵀ turns by
/// −R_a_bᵀ·θ and t_b_a = −R_a_bᵀ·t_a_b moves by −R_a_bᵀ·(dt + [t_a_b]×·θ).
inline PoseCovariance inversePoseCovariance(const Eigen::Isometry3d& T_a_b, const PoseCovariance& cov_a_b) {
  const Eigen::Matrix3d R_b_a = T_a_b.linear().transpose();
  const Eigen::Vector3d t = T_a_b.translation();
  Eigen::Matrix3d t_cross;
  t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  PoseCovariance J = PoseCovariance::Zero();  // d(θ_b, t_b_a) / d(θ_a, t_a_b)
  J.topLeftCorner<3, 3>() = -R_b_a;
  J.bottomLeftCorner<3, 3>() = -R_b_a * t_cross;
  J.bottomRightCorner<3, 3>() = -R_b_a;
  return J * cov_a_b * J.transpose();
}

/// The per-axis standard deviations of a pose covariance (valid when every one is finite; a NaN
/// variance stays NaN, a rounding-negative one is 0).
inline PoseStddev poseStddev(const PoseCovariance& cov) {
  PoseStddev sd;
  for (int i = 0; i < 3; ++i) {
    sd.rotation_deg[i] = std::sqrt(std::max(cov(i, i), 0.0)) * 180.0 / M_PI;
    sd.translation_m[i] = std::sqrt(std::max(cov(3 + i, 3 + i), 0.0));
  }
  sd.valid = sd.rotation_deg.allFinite() && sd.translation_m.allFinite();
  return sd;
}

}  // namespace telesphere::calib
