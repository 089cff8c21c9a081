// SPDX-License-Identifier: MIT
/// @brief ViewCoverage (see view_coverage.h).
#include "calib/view_coverage.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace telesphere::calib {

double polarAngleDeg(const GenericCamera& camera, const Eigen::Vector2d& px) {
  Eigen::Vector3d d;
  if (!camera.unproject(px, d) || !d.allFinite() || d.norm() == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return std::acos(std::clamp(d.normalized().z(), -1.0, 1.0)) * 180.0 / M_PI;
}

ViewCoverage::ViewCoverage(const GenericCamera& camera, int width, int height, const CoverageOptions& options)
    : camera_(camera), width_(width), height_(height), options_(options) {
  options_.grid_cols = std::max(1, options_.grid_cols);
  options_.grid_rows = std::max(1, options_.grid_rows);
  options_.polar_bin_deg = std::clamp(options_.polar_bin_deg, 0.5, 90.0);
  // The widest angle the image itself reaches: sample its border (the rim of a circular fisheye
  // image lies inside it; pixels outside the model's domain do not count).
  for (int i = 0; i <= 200; ++i) {
    const double s = double(i) / 200.0;
    for (const Eigen::Vector2d& px :
         {Eigen::Vector2d(s * (width - 1), 0), Eigen::Vector2d(s * (width - 1), height - 1),
          Eigen::Vector2d(0, s * (height - 1)), Eigen::Vector2d(width - 1, s * (height - 1)),
          Eigen::Vector2d(s * (width - 1), s * (height - 1)), Eigen::Vector2d(s * (width - 1), (1 - s) * (height - 1))}) {
      const double a = polarAngleDeg(camera_, px);
      if (std::isfinite(a)) image_max_polar_deg_ = std::max(image_max_polar_deg_, a);
    }
  }
  double edge = options_.polar_max_deg > 0 ? options_.polar_max_deg : image_max_polar_deg_;
  edge = std::min(edge, camera_.maxAngle() * 180.0 / M_PI);
  const int bins = std::max(1, int(std::ceil(edge / options_.polar_bin_deg - 1e-9)));
  polar_.assign(std::size_t(bins), 0);
  // Each bin's share of the image, from every 4th pixel of every 4th row.
  image_share_.assign(std::size_t(bins), 0.0);
  int samples = 0;
  for (int v = 0; v < height; v += 4)
    for (int u = 0; u < width; u += 4) {
      ++samples;
      const double a = polarAngleDeg(camera_, Eigen::Vector2d(u, v));
      if (std::isfinite(a)) image_share_[std::min(std::size_t(bins) - 1, std::size_t(a / options_.polar_bin_deg))] += 1.0;
    }
  for (double& s : image_share_) s /= std::max(1, samples);
  // Each bin's radial scale in its middle (where a tag centred in the ring lies): the largest over
  // 72 azimuths whose rays land in the image (a lens beyond 180° squeezes its rim radially; a tag
  // there is read only while its cells still span pixels).
  radial_px_per_deg_.assign(std::size_t(bins), 0.0);
  const auto ray = [](double polar_deg, double azimuth) {
    const double a = polar_deg * M_PI / 180.0;
    return Eigen::Vector3d(std::sin(a) * std::cos(azimuth), std::sin(a) * std::sin(azimuth), std::cos(a));
  };
  const auto inImage = [&](const Eigen::Vector2d& px) {
    return px.allFinite() && px.x() >= 0 && px.y() >= 0 && px.x() <= width - 1 && px.y() <= height - 1;
  };
  constexpr double kStepDeg = 0.1;
  for (int b = 0; b < bins; ++b) {
    const double middle = (b + 0.5) * options_.polar_bin_deg;
    for (int k = 0; k < 72; ++k) {
      const double azimuth = k * 5.0 * M_PI / 180.0;
      Eigen::Vector2d p0, p1;
      if (!camera_.project(ray(middle - 0.5 * kStepDeg, azimuth), p0) ||
          !camera_.project(ray(middle + 0.5 * kStepDeg, azimuth), p1) ||
          !inImage(p0) || !inImage(p1))
        continue;
      radial_px_per_deg_[std::size_t(b)] = std::max(radial_px_per_deg_[std::size_t(b)], (p1 - p0).norm() / kStepDeg);
    }
  }
  cells_.assign(std::size_t(options_.grid_cols * options_.grid_rows), 0);
}

void ViewCoverage::add(const TargetObservation& view) {
  for (const Eigen::Vector2d& px : view.corners_px) {
    if (!(px.x() >= -0.5 && px.y() >= -0.5 && px.x() < width_ - 0.5 && px.y() < height_ - 0.5)) continue;
    const int col = std::min(options_.grid_cols - 1, int((px.x() + 0.5) / width_ * options_.grid_cols));
    const int row = std::min(options_.grid_rows - 1, int((px.y() + 0.5) / height_ * options_.grid_rows));
    ++cells_[std::size_t(row * options_.grid_cols + col)];
    const double a = polarAngleDeg(camera_, px);
    if (std::isfinite(a)) ++polar_[std::min(polar_.size() - 1, std::size_t(a / options_.polar_bin_deg))];
    ++corners_;
  }
}

void ViewCoverage::clear() {
  std::fill(cells_.begin(), cells_.end(), 0);
  std::fill(polar_.begin(), polar_.end(), 0);
  corners_ = 0;
}

double ViewCoverage::gridCoverage() const {
  return double(std::count_if(cells_.begin(), cells_.end(), [](int n) { return n > 0; })) / double(cells_.size());
}

int ViewCoverage::polarBinsReached() const {
  return int(std::count_if(polar_.begin(), polar_.end(), [](int n) { return n > 0; }));
}

std::string ViewCoverage::describe() const {
  const int cells = int(std::count_if(cells_.begin(), cells_.end(), [](int n) { return n > 0; }));
  char buf[200];
  std::snprintf(buf, sizeof buf, "grid %d/%zu cells · polar bins %d/%d (to %.0f°) · %d corners", cells, cells_.size(),
                polarBinsReached(), polarBins(), polarBins() * options_.polar_bin_deg, corners_);
  return buf;
}

}  // namespace telesphere::calib
