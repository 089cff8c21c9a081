// SPDX-License-Identifier: MIT
/// @brief Synthetic images of planar calibration targets seen through a known camera model: the
///        ground truth of the detection and calibration tests and of `telesphere-bench calib`
///        (and reusable by the synthetic camera of the video path).
///
/// Per pixel, n×n sub-samples (area sampling by supersampling): each sub-sample is unprojected
/// through the true model, its ray intersected with the target plane (z = 0 of the target frame)
/// and the target's texture sampled there; the pixel is the mean. Pixels outside the model's
/// image region are black (0), rays that miss the target see a uniform background.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <string>

#include "calib/aprilgrid.h"
#include "calib/generic_camera.h"
#include "calib/gray_image.h"

namespace telesphere::calib {

/// Intensity (0…255) of a planar target at (x, y) metres in its own frame (z = 0), or a negative
/// value where the ray misses the target.
using TargetTexture = std::function<int(double x, double y)>;

/// kalibr's printed Aprilgrid in the board frame of calib/aprilgrid.h: 36h11 tags with a 2-bit
/// black border, each tag printed rotated by 180° like kalibr does, white paper with a margin of
/// one tag size around the grid and, when `corner_squares`, kalibr's black squares in the gaps
/// between tag corners.
TargetTexture aprilGridTexture(const AprilGrid& grid, bool corner_squares = true);

/// An ArUco marker of `dictionary` (see arucoDictionaryNames()), 1-bit border, edge `size`
/// metres, centred at the origin of the marker frame (OpenCV's convention: x right, y up, z out
/// of the printed face; corner 0 at (−size/2, size/2)), on white paper with a margin of size/2.
TargetTexture arucoMarkerTexture(const std::string& dictionary, int id, double size);

struct RenderOptions {
  int background = 96;         ///< intensity of rays that miss the target
  int supersampling = 3;       ///< n×n sub-samples per pixel (≥ 1)
  double noise_sigma = 0.0;    ///< Gaussian intensity noise added per pixel (grey levels)
  std::uint32_t noise_seed = 1;
};

/// Renders `texture` placed at T_cam_target (maps target points into the camera's optical
/// frame, metres) into a width×height image of `camera`.
GrayImage renderTarget(const GenericCamera& camera, int width, int height,
                       const Eigen::Isometry3d& T_cam_target, const TargetTexture& texture,
                       const RenderOptions& options = {});

}  // namespace telesphere::calib
