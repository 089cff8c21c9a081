// SPDX-License-Identifier: MIT
/// @brief The same camera at another image resolution (a binned or resized stream, or a demo run
///        at less than the calibrated 4K): focal lengths and principal point scale with the image,
///        the remaining (dimensionless) parameters of every model here stay as they are.
///
/// Pixel convention of the project: pixel (0, 0)'s centre is at (0, 0), so the image spans
/// [−0.5, w − 0.5]; scaling by s maps c to s·(c + 0.5) − 0.5.
#pragma once

#include <optional>
#include <string>

#include "calib/system_calibration.h"

namespace telesphere::calib {

/// `calibration` rescaled to width×height (each axis by its own factor); nothing, with the reason
/// in *error, for a non-positive size or parameters the model then refuses.
inline std::optional<CameraCalibration> atResolution(const CameraCalibration& calibration,
                                                     int width, int height, std::string* error) {
  if (width <= 0 || height <= 0 || calibration.width <= 0 || calibration.height <= 0) {
    *error = "cannot scale camera " + calibration.label + " to " + std::to_string(width) + "x" +
             std::to_string(height);
    return std::nullopt;
  }
  const double sx = double(width) / calibration.width, sy = double(height) / calibration.height;
  Eigen::VectorXd params = calibration.camera.params();  // fx, fy, cx, cy first in every model
  params[0] *= sx;
  params[1] *= sy;
  params[2] = sx * (params[2] + 0.5) - 0.5;
  params[3] = sy * (params[3] + 0.5) - 0.5;
  auto camera = GenericCamera::create(calibration.camera.modelName(), params, error);
  if (!camera) return std::nullopt;
  return CameraCalibration{calibration.label, *camera, width, height};
}

}  // namespace telesphere::calib
