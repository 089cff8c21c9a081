// SPDX-License-Identifier: MIT
/// @brief Sub-pixel corners of a square marker from its four sides' edges: each side's edge is
///        located across it at many points away from the corners (the centroid of the intensity
///        gradient along the side's normal), a low-order curve is fitted to those points (a
///        fisheye bends a side), and each corner is where its two sides' curves meet.
///
/// Why not OpenCV's refinements: a marker's outer corners are L-shaped (black square on white
/// paper), not the saddle points cornerSubPix is made for. Blur rounds an L-corner and
/// cornerSubPix then settles inside it: on rendered 10 cm markers at 0.45–0.8 m through the
/// 1280×1024 >180° lens, CORNER_REFINE_SUBPIX's corners sit 0.12 px inside the true ones on
/// average (0.22 px on aliased renders; `telesphere-bench calib`, table "marker corners"). While
/// choosing, OpenCV's other refinements measured worse on the same 60 renders: CONTOUR and none
/// 0.54 px inside, APRILTAG 0.04 px outside but 0.67 px RMS. The marker then looks smaller, hence
/// farther: in the simulated hand-eye runs that bias put T_robot_mount 4–6 mm off, 3–4 of its own
/// standard deviations, in 12 runs of 12. Edges away from the corner are steps whose gradient
/// centroid a symmetric blur does not move.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "calib/gray_image.h"

namespace telesphere::calib {

struct MarkerEdgeOptions {
  /// The part of each side whose edge is measured, as fractions of the side from its first corner.
  /// The ends, where the two edges blur into each other, are left out; the less is left out, the
  /// less the curves are extrapolated to the corners: 0.2–0.8 gave 0.16 px RMS on rendered markers,
  /// 0.1–0.9 0.066 px, 0.05–0.95 0.052 px (aliased renders: 0.47, 0.23, 0.19 px).
  double side_from = 0.05, side_to = 0.95;
  /// Half width of the search across the edge, px; also limited to 0.4 of a marker cell so the
  /// search never reaches the data cells behind the one-cell black border.
  double search_half_width_px = 3.0;
  int cells_across = 6;  ///< cells on a side, border included (4×4 ArUco with its 1-bit border: 6)
  /// Degree of the curve fitted per side: 1 a straight line, 2 a parabola (a fisheye's bend).
  int side_degree = 2;
  int min_edge_points = 6;  ///< per side; fewer (a side in shadow, cut by the image border): no result
};

/// The four corners refined from `initial` (in order around the marker, as OpenCV's detector
/// gives them, within about a pixel of the truth), px with pixel centres at integers; nothing
/// when a side's edge cannot be measured (too small, out of the image, no contrast).
std::optional<std::array<Eigen::Vector2d, 4>> refineMarkerCornersFromEdges(
    const GrayImage& image, const std::array<Eigen::Vector2d, 4>& initial, const MarkerEdgeOptions& options = {});

}  // namespace telesphere::calib
