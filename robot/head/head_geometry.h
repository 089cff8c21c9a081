// SPDX-License-Identifier: MIT
/// @brief HeadGeometry: where the stereo cameras sit on the head-arm flange, and the virtual
///        robot `head` frame derived from them (DESIGN.md §2).
///
/// Inputs come from calibration (T_flange_cam_l, the paper's T_cam, and the stereo extrinsic
/// T_cam_l_cam_r); until the system calibration struct exists they are plain parameters.
/// The head frame: origin at the midpoint of the two optical centres; axes x forward, y left,
/// z up, taken from cam_l's optical frame (z forward, x right, y down): x_head = z_cam_l,
/// y_head = −x_cam_l, z_head = −y_cam_l. Departure: a slight vergence or roll of cam_r is not
/// averaged in; the head frame follows the left camera.
#pragma once

#include <Eigen/Geometry>

namespace telesphere::robot::head {

struct HeadGeometry {
  Eigen::Isometry3d T_flange_cam_l = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_cam_l_cam_r = Eigen::Isometry3d::Identity();

  /// Rotation taking head-frame axes into cam_l optical axes (columns: head x, y, z in cam_l).
  static Eigen::Matrix3d R_cam_head();

  Eigen::Isometry3d T_flange_head() const;
  Eigen::Isometry3d T_head_cam_l() const;
  Eigen::Isometry3d T_head_cam_r() const;

  /// An example mount used by tests and benchmarks (not a calibration): both cameras look out
  /// along the flange z axis, cam_l optical axes parallel to the flange axes, optical centres
  /// 50 mm in front of the flange, 65 mm baseline.
  static HeadGeometry example();
};

}  // namespace telesphere::robot::head
