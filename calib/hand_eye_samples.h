// SPDX-License-Identifier: MIT
/// @brief The sample file of `telesphere-calib handeye` (YAML):
///   marker: {dictionary: DICT_4X4_50, id: 0, size: 0.1}     # ArUco marker on the wrist, metres
///   samples:
///     - t_ns: 1700000000000000000                           # capture time of the image pair
///       T_robot_flange: {translation: [x, y, z], rotation_xyzw: [qx, qy, qz, qw]}  # head arm FK
///       T_mount_wrist: {translation: [...], rotation_xyzw: [...]}                  # manipulator FK
///       image_l: left/000.png        # relative to the sample file; or instead
///       corners_l: [[u, v], [u, v], [u, v], [u, v]]   # marker corners, OpenCV order, px
///       image_r: right/000.png       # or corners_r (both optional: a camera may miss the marker)
/// Poses come from the arms' forward kinematics (the robot side writes them); images are
/// searched for the marker with calib/target_detection.h.
#pragma once

#include <functional>
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

/// Reads the sample file and detects the marker in its images (progress one line per sample).
/// Unreadable images are errors naming the file and the sample.
FileResult<HandEyeSampleFile> loadHandEyeSamples(
    const std::string& path, const std::function<void(const std::string&)>& progress = {});

}  // namespace telesphere::calib
