// SPDX-License-Identifier: MIT
/// @brief Detection of kalibr's Aprilgrid and of the hand-eye ArUco marker with OpenCV's aruco
///        module (DICT_APRILTAG_36h11 with a 2-bit border for the grid) and sub-pixel corner
///        refinement. Corners are returned with kalibr/Basalt ids (calib/aprilgrid.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "calib/aprilgrid.h"
#include "calib/gray_image.h"

namespace telesphere::calib {

/// Corners of a target seen in one image: pixels (origin at the centre of the top-left pixel)
/// and the target's corner ids, in the same order.
struct TargetObservation {
  std::vector<int> corner_ids;
  std::vector<Eigen::Vector2d> corners_px;
  int tags_detected = 0;  ///< tags of the target found (before the border and count checks)
  bool empty() const { return corner_ids.empty(); }
};

/// How the hand-eye marker's corners are refined after OpenCV found them.
enum class MarkerCornerRefinement {
  kEdges,         ///< from the sides' edges (marker_edge_corners.h); cornerSubPix's where that fails
  kCornerSubPix,  ///< OpenCV's cornerSubPix alone: 0.12 px inside the true corners on average
};

struct DetectionOptions {
  int min_tags = 4;               ///< a view with fewer tags yields no corners
  double border_margin_px = 4.0;  ///< corners closer than this to the image border are dropped
  int subpixel_window_px = 4;     ///< half size of the cornerSubPix window
  MarkerCornerRefinement marker_corners = MarkerCornerRefinement::kEdges;  ///< detectArucoMarker only
};

/// The Aprilgrid's corners in `image`; empty when fewer than options.min_tags tags are found.
TargetObservation detectAprilGrid(const GrayImage& image, const AprilGrid& grid,
                                  const DetectionOptions& options = {});

/// Names of the ArUco dictionaries accepted for the hand-eye marker ("DICT_4X4_50", …).
std::vector<std::string> arucoDictionaryNames();

/// The four corners (OpenCV order: top-left, top-right, bottom-right, bottom-left of the marker
/// as printed) of marker `id` of `dictionary`, sub-pixel refined (options.marker_corners); nothing when the marker is not
/// found or a corner is within options.border_margin_px of the border. Throws
/// std::invalid_argument for an unknown dictionary name (a programmer or configuration error
/// checked by callers through arucoDictionaryNames()).
std::optional<std::array<Eigen::Vector2d, 4>> detectArucoMarker(const GrayImage& image,
                                                                const std::string& dictionary,
                                                                int id,
                                                                const DetectionOptions& options = {});

/// Reads an image file as 8-bit grey; nothing when it cannot be read.
std::optional<GrayImage> readGrayImage(const std::string& path);
/// Writes an 8-bit grey image (format from the extension); false on failure.
bool writeGrayImage(const GrayImage& image, const std::string& path);

}  // namespace telesphere::calib
