// SPDX-License-Identifier: MIT
/// @brief What the operator saw against what they should have seen (issue: end-to-end truth),
///        geometrically: for each eye pixel (every `stride`-th in both directions), the eye ray
///        (the eye's XrFovf pinhole at T_robot_eye = T_robot_vr · T_vr_hmd · T_hmd_eye, with
///        T_robot_vr the robot's mapping and T_hmd_eye from the IPD, all independent of the
///        operator app's own composition) against the direction from the eye to the scene point
///        the pixel actually shows: the camera pixel the renderer sampled (its projection map),
///        unprojected through the TRUE calibration from the camera's TRUE pose at capture and met
///        with the known scene. The angle between them is the error, whatever its cause
///        (calibration, joint buffer, capture-time pose, mapping, eye poses, renderer, and the
///        sphere's own distortion γ while the eye is away from the camera). Moving objects are
///        taken where they were at capture.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "calib/system_calibration.h"
#include "robot/cameras/synthetic_scene.h"
#include "app/bench/truth/ground_truth_files.h"

namespace telesphere::truth {

struct EyeErrorOptions {
  int stride = 2;  ///< px between evaluated eye pixels, both directions
};

struct FrameEyeError {
  std::vector<double> error_deg;    ///< one per evaluated pixel that shows a scene point
  std::size_t evaluated = 0;        ///< eye pixels looked at
  std::size_t blind = 0;            ///< of those, showing no camera pixel (border)
  std::size_t no_scene = 0;         ///< showing a camera pixel whose ray meets nothing
  /// Left eye to left camera (true pose at capture), m: Δs of the paper's Fig. 7.
  double eye_camera_distance_m = 0;
  /// The stamped against the true left camera pose: position (m) and angle (deg).
  double stamp_position_error_m = 0, stamp_angle_error_deg = 0;
};

/// Evaluates one recorded frame (`map` from loadProjectionMap); `calibration` is the TRUE one.
/// Nothing when the robot truth lacks a camera pose or the mapping, or the camera sizes do not fit.
std::optional<FrameEyeError> evaluateEyeImages(const XrTruthFrame& frame, const std::vector<float>& map,
                                               const RobotTruthRow& robot, const calib::SystemCalibration& calibration,
                                               const robot::cameras::SyntheticScene& scene, const EyeErrorOptions& options,
                                               std::string* error);

/// q-quantile (0…1) of `values` by linear interpolation between order statistics (NaN if empty).
double quantile(std::vector<double> values, double q);

}  // namespace telesphere::truth
