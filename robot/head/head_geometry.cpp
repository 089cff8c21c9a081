// SPDX-License-Identifier: MIT
/// @brief HeadGeometry (see head_geometry.h).
#include "robot/head/head_geometry.h"

namespace telesphere::robot::head {

Eigen::Matrix3d HeadGeometry::R_cam_head() {
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(0, 0, 1);   // head x (forward) = optical z
  R.col(1) = Eigen::Vector3d(-1, 0, 0);  // head y (left) = −optical x
  R.col(2) = Eigen::Vector3d(0, -1, 0);  // head z (up) = −optical y
  return R;
}

Eigen::Isometry3d HeadGeometry::T_flange_head() const {
  Eigen::Isometry3d T_cam_l_head = Eigen::Isometry3d::Identity();
  T_cam_l_head.linear() = R_cam_head();
  T_cam_l_head.translation() = 0.5 * T_cam_l_cam_r.translation();
  return T_flange_cam_l * T_cam_l_head;
}

Eigen::Isometry3d HeadGeometry::T_head_cam_l() const {
  return T_flange_head().inverse() * T_flange_cam_l;
}

Eigen::Isometry3d HeadGeometry::T_head_cam_r() const { return T_head_cam_l() * T_cam_l_cam_r; }

HeadGeometry HeadGeometry::example() {
  HeadGeometry g;
  g.T_flange_cam_l = Eigen::Translation3d(-0.0325, 0.0, 0.05) * Eigen::Isometry3d::Identity();
  g.T_cam_l_cam_r = Eigen::Translation3d(0.065, 0.0, 0.0) * Eigen::Isometry3d::Identity();
  return g;
}

}  // namespace telesphere::robot::head
