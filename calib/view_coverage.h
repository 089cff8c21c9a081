// SPDX-License-Identifier: MIT
/// @brief How much of a camera's image the kept calibration views cover (issue #15), in two
///        ways that also work for lenses beyond 180°: an image grid (which cells hold a corner)
///        and polar-angle bins out to the rim (the angle between a corner's ray and the optical
///        axis, through the current camera model; a grid alone under-weights the rim, where a
///        fisheye squeezes the most angle into the fewest pixels). For a stereo pair, the views
///        seen by both cameras at once count separately (what the extrinsic needs).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calib/generic_camera.h"
#include "calib/target_detection.h"

namespace telesphere::calib {

struct CoverageOptions {
  int grid_cols = 8, grid_rows = 6;
  double polar_bin_deg = 10.0;
  double polar_max_deg = 0.0;  ///< the outermost bin's edge (0: the model's field of view, capped at the image)
};

class ViewCoverage {
 public:
  ViewCoverage(const GenericCamera& camera, int width, int height, const CoverageOptions& options = {});

  void add(const TargetObservation& view);
  void clear();

  int gridCols() const { return options_.grid_cols; }
  int gridRows() const { return options_.grid_rows; }
  /// Corners seen in cell (col, row), over all views added.
  int cellCount(int col, int row) const { return cells_[std::size_t(row * options_.grid_cols + col)]; }
  double gridCoverage() const;  ///< share of cells with at least one corner, 0…1

  /// Polar-angle bins [i·bin, (i+1)·bin) up to the edge the image reaches.
  int polarBins() const { return static_cast<int>(polar_.size()); }
  double polarBinDeg() const { return options_.polar_bin_deg; }
  int polarCount(int bin) const { return polar_[std::size_t(bin)]; }
  int polarBinsReached() const;
  /// The largest polar angle any pixel of the image sees (deg), through the camera model.
  double imageMaxPolarDeg() const { return image_max_polar_deg_; }
  /// The share of the image's pixels (0…1) whose polar angle falls into `bin` (the rim bins of a
  /// wide lens on a 16:9 sensor hold only the image's corners).
  double imageShare(int bin) const { return image_share_[std::size_t(bin)]; }
  /// How many pixels a degree of polar angle spans in the bin's middle (radially, through the
  /// model; the largest over the azimuths whose rays land in the image; 0 when none does).
  double radialPxPerDeg(int bin) const { return radial_px_per_deg_[std::size_t(bin)]; }

  /// "grid 31/48 cells · polar bins 8/10 (to 100°) · 1234 corners".
  std::string describe() const;

 private:
  GenericCamera camera_;
  int width_, height_;
  CoverageOptions options_;
  double image_max_polar_deg_ = 0;
  std::vector<int> cells_, polar_;
  std::vector<double> image_share_, radial_px_per_deg_;
  int corners_ = 0;
};

/// The polar angle (deg) of pixel `px` through `camera`, or NaN when it does not unproject.
double polarAngleDeg(const GenericCamera& camera, const Eigen::Vector2d& px);

}  // namespace telesphere::calib
