// SPDX-License-Identifier: MIT
/// @brief The sample file of `telesphere-calib handeye` (YAML):
///   marker: {dictionary: DICT_4X4_50, id: 0, size: 0.1}     # ArUco marker on the wrist, metres
///   samples:
///     - t_ns: 1700000000000000000                           # capture time of the image pair
///       T_robot_flange: {translation: [x, y, z], rotation_xyzw: [qx, qy, qz, qw]}  # head arm FK
///       # or instead: q_head: [q1, q2, q3, q4, q5, q6]   # head-arm joint angles, rad, through
///       #   the head arm's forward kinematics (HeadArmForwardKinematics; telesphere-calib passes
///       #   the xArm 6 model of robot/arm/xarm6_kinematics.h)
///       T_mount_wrist: {translation: [...], rotation_xyzw: [...]}                  # manipulator FK
///       image_l: left/000.png        # relative to the sample file; or instead
///       corners_l: [[u, v], [u, v], [u, v], [u, v]]   # marker corners, OpenCV order, px
///       image_r: right/000.png       # or corners_r (both optional: a camera may miss the marker)
/// Poses come from the arms' forward kinematics (the robot side writes them); images are
/// searched for the marker with calib/target_detection.h.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calib/file_error.h"
#include "calib/hand_eye_calibration.h"

namespace telesphere::calib {

struct HandEyeSampleFile {
  std::string dictionary = "DICT_4X4_50";
  int marker_id = 0;
  double marker_size = 0.1;  ///< metres
  std::vector<HandEyeSample> samples;
};

/// Forward kinematics of the head arm: T_robot_flange from its joint angles q (rad); nothing when
/// q is not a valid joint vector (wrong count, not finite), with the reason in *error.
using HeadArmForwardKinematics =
    std::function<std::optional<Eigen::Isometry3d>(const std::vector<double>& q, std::string* error)>;

/// Reads the sample file and detects the marker in its images (progress one line per sample).
/// Unreadable images are errors naming the file and the sample. A sample gives either
/// T_robot_flange or q_head; q_head needs `head_fk` (an error naming the sample otherwise).
FileResult<HandEyeSampleFile> loadHandEyeSamples(
    const std::string& path, const std::function<void(const std::string&)>& progress = {},
    const HeadArmForwardKinematics& head_fk = {});

}  // namespace telesphere::calib
