// SPDX-License-Identifier: MIT
/// @brief The report of an intrinsic calibration: kalibr-style text summary (per camera model,
///        parameters ± standard deviation, reprojection RMS and mean, worst views, coverage,
///        T_cam_l_cam_r), a coverage picture, and its JSON file (written by
///        `telesphere-calib intrinsics`, read by `telesphere-calib report`).
#pragma once

#include <optional>
#include <string>

#include "calib/file_error.h"
#include "calib/gray_image.h"
#include "calib/intrinsic_calibration.h"

namespace telesphere::calib {

/// Fraction of a 16×16 grid of cells over the image that hold at least one corner.
double coverageFraction(const CameraIntrinsicResult& camera);

/// The image at 1/`scale` size: cells of the 16×16 grid shaded by their corner count, each corner
/// a white dot, its error drawn ×20 as a line, pixels outside the model's image region black.
GrayImage coverageImage(const CameraIntrinsicResult& camera, int scale = 2);

std::string kalibrStyleSummary(const IntrinsicResult& result);

std::optional<FileError> saveIntrinsicReport(const IntrinsicResult& result, const std::string& path);
FileResult<IntrinsicResult> loadIntrinsicReport(const std::string& path);

}  // namespace telesphere::calib
