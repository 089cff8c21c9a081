// SPDX-License-Identifier: MIT
/// @brief The system calibration (DESIGN.md §2, §6): intrinsics and resolution of each camera of
///        the stereo pair and the extrinsics T_cam_l_cam_r, T_flange_cam_l, T_robot_mount,
///        T_wrist_marker. Our own YAML format stores it (system_calibration_yaml.h); kalibr and
///        Basalt files import into and export from it (kalibr_camchain.h, basalt_calibration.h).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "calib/generic_camera.h"

namespace telesphere::calib {

struct CameraCalibration {
  std::string label;  ///< "cam_l" or "cam_r" (the frames of DESIGN.md §2)
  GenericCamera camera;
  int width = 0;   ///< image width, px
  int height = 0;  ///< image height, px
};

struct SystemCalibration {
  /// cameras[0] is the left camera (cam_l), cameras[1] the right one (cam_r); a single camera is
  /// allowed while only intrinsics are known.
  std::vector<CameraCalibration> cameras;
  /// Maps points from cam_r into cam_l; present iff there are two cameras.
  std::optional<Eigen::Isometry3d> T_cam_l_cam_r;
  /// Hand-eye results (paper eqs. 1–3), absent until hand-eye calibration has run.
  std::optional<Eigen::Isometry3d> T_flange_cam_l;
  std::optional<Eigen::Isometry3d> T_robot_mount;
  std::optional<Eigen::Isometry3d> T_wrist_marker;

  /// The first inconsistency as {field, message}, or nothing: camera count (1 or 2), labels
  /// cam_l/cam_r, resolution in (0, 32768], principal point inside the image, T_cam_l_cam_r
  /// present iff two cameras, every transform finite with an orthonormal rotation.
  std::optional<std::pair<std::string, std::string>> inconsistency() const;
};

}  // namespace telesphere::calib
