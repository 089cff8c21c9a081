// SPDX-License-Identifier: MIT
/// @brief Our system calibration file (YAML), version 1:
///
///   version: 1
///   cameras:
///     - label: cam_l
///       model: ds                      # ds | eucm | kb4 | pinhole
///       resolution: [3840, 2160]       # width, height in px
///       intrinsics: {fx: 930, fy: 931, cx: 1919.5, cy: 1079.5, xi: -0.18, alpha: 0.59}
///     - label: cam_r
///       ...
///   extrinsics:                        # T_a_b maps points from frame b into frame a (metres)
///     T_cam_l_cam_r: {translation: [0.064, 0, 0], rotation_xyzw: [0, 0, 0, 1]}
///     T_flange_cam_l: {...}            # optional until hand-eye calibration has run
///     T_robot_mount: {...}
///     T_wrist_marker: {...}
///
/// Intrinsics are named (the names of each model's kParamNames), so a file says what it means.
/// Reading rejects unknown fields, missing fields, parameters outside a model's domain and
/// inconsistent content, with an error naming the file, the line and the field. Numbers are
/// written with 17 significant digits, so a write-read round trip is exact.
#pragma once

#include <string>

#include "calib/file_error.h"
#include "calib/system_calibration.h"

namespace telesphere::calib {

inline constexpr int kSystemCalibrationVersion = 1;

/// Parses our YAML format; `path` only names the source in errors.
FileResult<SystemCalibration> parseSystemCalibrationYaml(const std::string& text,
                                                         const std::string& path);

/// Our YAML format for `calibration` (which must be consistent).
std::string toSystemCalibrationYaml(const SystemCalibration& calibration);

}  // namespace telesphere::calib
