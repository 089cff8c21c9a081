// SPDX-License-Identifier: MIT
/// @brief Depth proxies in double precision: the grid's tiles, its bilinear lookup, the
///        centre-weighted radius and the fixed-point ray–proxy intersection.
#include "xr/render/depth_proxy.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "xr/render/sphere_geometry.h"

namespace telesphere::xr::render {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

double radiusFromInverseDepth(double inverse_depth_per_m) {
  if (!(inverse_depth_per_m > 1.0 / kMaxProxyRadiusM)) return kMaxProxyRadiusM;
  return std::clamp(1.0 / inverse_depth_per_m, kMinProxyRadiusM, kMaxProxyRadiusM);
}

InverseDepthGrid::InverseDepthGrid(double tile_deg, float inverse_depth_per_m) : tile_deg_(tile_deg) {
  const double rows = 180.0 / tile_deg;
  if (!(tile_deg > 0.0 && tile_deg <= 90.0) || std::abs(rows - std::round(rows)) > 1e-9)
    throw std::invalid_argument("InverseDepthGrid: tile of " + std::to_string(tile_deg) +
                                " deg; it must divide 180 and be at most 90");
  rows_ = static_cast<int>(std::lround(rows));
  cols_ = 2 * rows_;
  values_.assign(static_cast<std::size_t>(rows_) * cols_, inverse_depth_per_m);
}

Eigen::Vector3d InverseDepthGrid::direction(double row, double col) const {
  const double lat = -90.0 * kDeg + row * tile_deg_ * kDeg;
  const double lon = -180.0 * kDeg + col * tile_deg_ * kDeg;
  return {std::cos(lat) * std::sin(lon), -std::sin(lat), std::cos(lat) * std::cos(lon)};
}

double InverseDepthGrid::sample(const Eigen::Vector3d& d) const {
  const double n = d.norm();
  const double lat = std::asin(std::clamp(-d.y() / n, -1.0, 1.0));
  const double lon = std::atan2(d.x(), d.z());
  // Continuous tile coordinates with tile centres at integers.
  const double r = std::clamp((lat / kDeg + 90.0) / tile_deg_ - 0.5, 0.0, rows_ - 1.0);
  const double c = (lon / kDeg + 180.0) / tile_deg_ - 0.5;
  const int r0 = std::min(static_cast<int>(r), rows_ - 2), r1 = r0 + 1;  // rows_ ≥ 2 (tiles ≤ 90°)
  const double fr = r - r0;
  const int c_floor = static_cast<int>(std::floor(c));
  const double fc = c - c_floor;
  const int c0 = ((c_floor % cols_) + cols_) % cols_, c1 = (c0 + 1) % cols_;
  return (1 - fr) * ((1 - fc) * at(r0, c0) + fc * at(r0, c1)) + fr * ((1 - fc) * at(r1, c0) + fc * at(r1, c1));
}

double centreWeightedRadius(const InverseDepthGrid& grid, const Eigen::Vector3d& centre, double sigma_rad) {
  const Eigen::Vector3d axis = centre.normalized();
  std::vector<std::pair<double, double>> weighted;  // inverse depth, weight
  double total = 0;
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      const Eigen::Vector3d dir = grid.tileCentre(row, col);
      const double theta = std::acos(std::clamp(dir.dot(axis), -1.0, 1.0));
      const double solid_angle = std::sqrt(std::max(0.0, 1.0 - dir.y() * dir.y()));  // cos(latitude)
      const double w = solid_angle * std::exp(-theta * theta / (2.0 * sigma_rad * sigma_rad));
      if (w < 1e-12) continue;
      weighted.emplace_back(grid.at(row, col), w);
      total += w;
    }
  if (weighted.empty()) return radiusFromInverseDepth(grid.sample(axis));
  std::sort(weighted.begin(), weighted.end());
  double acc = 0;
  for (const auto& [inverse_depth, w] : weighted) {
    acc += w;
    if (acc >= 0.5 * total) return radiusFromInverseDepth(inverse_depth);
  }
  return radiusFromInverseDepth(weighted.back().first);
}

std::optional<Eigen::Vector3d> sphereProxyHit(double radius_m, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const std::optional<double> t = sphereFarHit(o, d, o.squaredNorm() - radius_m * radius_m);
  if (!t) return std::nullopt;
  return o + *t * d;
}

std::optional<Eigen::Vector3d> gridProxyHit(const InverseDepthGrid& grid, const Eigen::Vector3d& o,
                                            const Eigen::Vector3d& d, int steps) {
  double r = radiusFromInverseDepth(grid.sample(d));
  std::optional<Eigen::Vector3d> p = sphereProxyHit(r, o, d);
  for (int k = 0; k < steps && p; ++k) {
    if (p->squaredNorm() <= 0.0) break;  // at the camera centre: no direction to look up
    r = radiusFromInverseDepth(grid.sample(*p));
    p = sphereProxyHit(r, o, d);
  }
  return p;
}

}  // namespace telesphere::xr::render
