// SPDX-License-Identifier: MIT
/// @brief kalibr's Aprilgrid calibration target (AprilTag 36h11 tags in a grid) and its corner
///        numbering, read from kalibr's target YAML:
///          target_type: 'aprilgrid'
///          tagCols: 6          # tags per row
///          tagRows: 6          # tags per column
///          tagSize: 0.088      # edge of a tag incl. its 2-bit black border, metres
///          tagSpacing: 0.3     # gap between tags as a ratio of tagSize
///
/// Board frame `board` (kalibr/Basalt): origin at the outer bottom-left corner of tag 0 seen from
/// the printed side, x along a row of tags (right), y up the columns, z out of the printed face
/// (towards a camera that sees the board). Tag id = row·tagCols + col, tag 0 bottom-left.
/// Corner id = 4·tag + k with kalibr/Basalt's k: 0 bottom-left, 1 bottom-right, 2 top-right,
/// 3 top-left of the tag. OpenCV's aruco returns corner j = (1 − k) mod 4 for kalibr's k
/// (kalibr prints each tag rotated by 180° relative to the tag's code image; pinned by
/// tests/calib/test_aprilgrid_detection.cpp).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calib/file_error.h"

namespace telesphere::calib {

struct AprilGrid {
  int tag_cols = 6;
  int tag_rows = 6;
  double tag_size = 0.088;   ///< metres
  double tag_spacing = 0.3;  ///< ratio of tag_size

  int numTags() const { return tag_cols * tag_rows; }
  int numCorners() const { return 4 * numTags(); }
  /// Distance between the origins of neighbouring tags, metres: tag_size·(1 + tag_spacing).
  double pitch() const { return tag_size * (1.0 + tag_spacing); }
  /// Position of corner `corner_id` = 4·tag + k in the board frame (z = 0), metres.
  Eigen::Vector3d cornerPosition(int corner_id) const;
  /// All corners, index = corner id.
  std::vector<Eigen::Vector3d> cornerPositions() const;
  /// Board width and height covered by the tags, metres.
  double width() const { return tag_cols * pitch() - tag_size * tag_spacing; }
  double height() const { return tag_rows * pitch() - tag_size * tag_spacing; }
};

/// kalibr's corner k ↔ OpenCV aruco's corner index (1 − k) mod 4 (and back: the map is its own
/// inverse).
constexpr int kalibrToOpenCvCorner(int k) { return ((1 - k) % 4 + 4) % 4; }

/// Reads a kalibr target YAML (target_type 'aprilgrid'); errors name the file, line and field.
FileResult<AprilGrid> loadAprilGrid(const std::string& path);
FileResult<AprilGrid> parseAprilGrid(const std::string& text, const std::string& path);

}  // namespace telesphere::calib
