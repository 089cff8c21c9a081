// SPDX-License-Identifier: MIT
/// @brief Depth proxies in double precision: the grid's tiles, its lookup (bilinear, nearest at edges), the
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

namespace {

/// The four tiles around a direction and its weights: rows clamped at the poles and columns
/// wrapping at the seam, as a texture with clamp-to-edge in t and repeat in s (the shader's
/// textureGather).
struct TileQuad {
  float v00, v01, v10, v11;  ///< rows r0, r1 × columns c0, c1
  double fr, fc;             ///< weights of row r1 and column c1
  double bilinear() const { return (1 - fr) * ((1 - fc) * v00 + fc * v01) + fr * ((1 - fc) * v10 + fc * v11); }
};

TileQuad quadAround(const InverseDepthGrid& grid, double tile_deg, const Eigen::Vector3d& d) {
  const double n = d.norm();
  const double lat = std::asin(std::clamp(-d.y() / n, -1.0, 1.0));
  const double lon = std::atan2(d.x(), d.z());
  // Continuous tile coordinates with tile centres at integers.
  const double r = (lat / kDeg + 90.0) / tile_deg - 0.5;
  const double c = (lon / kDeg + 180.0) / tile_deg - 0.5;
  const double r_floor = std::floor(r), c_floor = std::floor(c);
  const int rows = grid.rows(), cols = grid.cols();
  const int r0 = std::clamp(static_cast<int>(r_floor), 0, rows - 1), r1 = std::clamp(static_cast<int>(r_floor) + 1, 0, rows - 1);
  const int c0 = ((static_cast<int>(c_floor) % cols) + cols) % cols, c1 = (c0 + 1) % cols;
  return {grid.at(r0, c0), grid.at(r0, c1), grid.at(r1, c0), grid.at(r1, c1), r - r_floor, c - c_floor};
}

}  // namespace

double InverseDepthGrid::sample(const Eigen::Vector3d& d) const {
  return quadAround(*this, tile_deg_, d).bilinear();
}

double InverseDepthGrid::sampleNearestAtEdges(const Eigen::Vector3d& d, double edge_jump_per_m) const {
  const TileQuad q = quadAround(*this, tile_deg_, d);
  const float hi = std::max({q.v00, q.v01, q.v10, q.v11}), lo = std::min({q.v00, q.v01, q.v10, q.v11});
  return static_cast<double>(hi) - lo > edge_jump_per_m ? hi : q.bilinear();
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
                                            const Eigen::Vector3d& d, int steps, double edge_slope_per_m_per_deg) {
  const double edge_jump_per_m = edge_slope_per_m_per_deg * grid.tileDeg();
  double r = radiusFromInverseDepth(grid.sampleNearestAtEdges(d, edge_jump_per_m));
  std::optional<Eigen::Vector3d> p = sphereProxyHit(r, o, d);
  for (int k = 0; k < steps && p; ++k) {
    if (p->squaredNorm() <= 0.0) break;  // at the camera centre: no direction to look up
    r = radiusFromInverseDepth(grid.sampleNearestAtEdges(*p, edge_jump_per_m));
    p = sphereProxyHit(r, o, d);
  }
  return p;
}

}  // namespace telesphere::xr::render
