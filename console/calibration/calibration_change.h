// SPDX-License-Identifier: MIT
/// @brief Applying a wizard's result live (issue #15, DESIGN.md §6): what the robot should use
///        next, and how much that differs from what it uses now, in figures a supervisor can
///        judge before pressing Apply.
///
/// A wizard measures part of the system calibration: the intrinsics wizard both cameras' models
/// and T_cam_l_cam_r, the hand-eye wizard T_flange_cam_l (with T_robot_mount, T_wrist_marker).
/// Only that part replaces the calibration in use; the rest stays as the robot has it (a hand-eye
/// result never brings back the intrinsics it was loaded with, an intrinsics result never an old
/// hand-eye from the wizard's start file).
#pragma once

#include <string>
#include <vector>

#include "calib/system_calibration.h"

namespace telesphere::console::calibration {

enum class MeasuredParts {
  kCameras,  ///< both cameras' models and T_cam_l_cam_r (intrinsics and stereo wizard)
  kHandEye,  ///< T_flange_cam_l, T_robot_mount, T_wrist_marker (hand-eye wizard)
};

/// `in_use` with the measured part of `result` put in.
calib::SystemCalibration withMeasured(const calib::SystemCalibration& in_use, const calib::SystemCalibration& result,
                                      MeasuredParts parts);

/// One line of the comparison: what, how much, and in which unit.
struct CalibrationDifference {
  std::string what;       ///< "T_flange_cam_l", "cam_l image", …
  double value = 0;       ///< translation mm, rotation °, or px
  std::string unit;       ///< "mm", "°", "px"
  std::string detail;     ///< "ds → kb4", "max over the image (median 0.4 px)", …
};

/// How `to` differs from `from`: each transform's translation (mm) and rotation (°), and for each
/// camera how far the image moves: pixels unprojected through `from`'s model and projected
/// through `to`'s (same resolution: `to` is scaled to `from`'s), max over a 16×16 grid inside the
/// image (only pixels both models can map), the median in the detail. Transforms absent in
/// either are skipped.
std::vector<CalibrationDifference> differences(const calib::SystemCalibration& from,
                                               const calib::SystemCalibration& to);

}  // namespace telesphere::console::calibration
