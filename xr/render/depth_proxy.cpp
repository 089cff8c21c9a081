// SPDX-License-Identifier: MIT
/// @brief Depth proxies in double precision: the grid's tiles, its lookup (bilinear, one tile at edges), the
///        centre-weighted radius and where an eye ray meets the grid (the march and its fixed-point
///        predecessor).
#include "xr/render/depth_proxy.h"

#include <algorithm>
#include <cassert>
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

double InverseDepthGrid::sampleKeepingEdges(const Eigen::Vector3d& d, double edge_jump_per_m, GridEdgeTile tile) const {
  const TileQuad q = quadAround(*this, tile_deg_, d);
  const float hi = std::max({q.v00, q.v01, q.v10, q.v11}), lo = std::min({q.v00, q.v01, q.v10, q.v11});
  if (!(static_cast<double>(hi) - lo > edge_jump_per_m)) return q.bilinear();
  if (tile == GridEdgeTile::kNearestDepth) return hi;
  return q.fr < 0.5 ? (q.fc < 0.5 ? q.v00 : q.v01) : (q.fc < 0.5 ? q.v10 : q.v11);
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

GridProxyParams gridProxyParams(const InverseDepthGrid& grid, double edge_slope_per_m_per_deg, double march_step_tiles,
                                int refine_steps) {
  GridProxyParams params;
  params.edge_jump_per_m = edge_slope_per_m_per_deg * grid.tileDeg();
  params.inverse_depth_bottom_per_m = 1.0 / kMaxProxyRadiusM;
  double top = params.inverse_depth_bottom_per_m;
  const float* v = grid.data();
  for (std::size_t i = 0, n = static_cast<std::size_t>(grid.rows()) * grid.cols(); i < n; ++i)
    top = std::max(top, 1.0 / radiusFromInverseDepth(v[i]));  // NaN and infinity as every lookup bounds them
  params.inverse_depth_top_per_m = top;
  assert(march_step_tiles > 0.0);  // checkRenderSettings refuses the rest
  params.march_step_rad = march_step_tiles * grid.tileDeg() * kDeg;
  params.refine_steps = refine_steps;
  return params;
}

int gridMarchSteps(const GridProxyParams& params, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const double sweep_rad = o.cross(d).norm() * (params.inverse_depth_top_per_m - params.inverse_depth_bottom_per_m);
  return static_cast<int>(std::clamp(std::ceil(sweep_rad / params.march_step_rad), 1.0, double(kGridMarchMaxSteps)));
}

namespace {

/// The ray's point at inverse depth ρ from the camera (the far root), and the grid's bounded
/// inverse depth there minus ρ: negative while the point lies in front of the surface.
struct MarchPoint {
  std::optional<Eigen::Vector3d> p;
  double g = 0;
};

class RayOnGrid {
 public:
  RayOnGrid(const InverseDepthGrid& grid, const GridProxyParams& params, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
            int* lookups)
      : grid_(grid), params_(params), o_(o), d_(d), lookups_(lookups) {}

  MarchPoint at(double inverse_depth) const {
    MarchPoint m{sphereProxyHit(1.0 / inverse_depth, o_, d_), 0.0};
    if (m.p) m.g = 1.0 / radiusFromInverseDepth(lookup(*m.p)) - inverse_depth;
    return m;
  }
  double lookup(const Eigen::Vector3d& p) const {
    if (lookups_) ++*lookups_;
    return grid_.sampleKeepingEdges(p, params_.edge_jump_per_m, params_.edge_tile);
  }

 private:
  const InverseDepthGrid& grid_;
  const GridProxyParams& params_;
  const Eigen::Vector3d &o_, &d_;
  int* lookups_;
};

}  // namespace

std::optional<Eigen::Vector3d> gridProxyHit(const InverseDepthGrid& grid, const GridProxyParams& params,
                                            const Eigen::Vector3d& o, const Eigen::Vector3d& d, int* lookups) {
  const RayOnGrid ray(grid, params, o, d, lookups);
  if (!std::isfinite(params.march_step_rad)) {  // fixed-point steps from the ray's own direction
    std::optional<Eigen::Vector3d> p = sphereProxyHit(radiusFromInverseDepth(ray.lookup(d)), o, d);
    for (int k = 0; k < params.refine_steps && p; ++k) {
      if (p->squaredNorm() <= 0.0) break;  // at the camera centre: no direction to look up
      p = sphereProxyHit(radiusFromInverseDepth(ray.lookup(*p)), o, d);
    }
    return p;
  }
  const double top = params.inverse_depth_top_per_m, bottom = params.inverse_depth_bottom_per_m;
  double a = top;
  MarchPoint ma = ray.at(a);
  if (ma.p && ma.g >= 0.0) return ma.p;
  const int n = gridMarchSteps(params, o, d);
  double b = top;
  MarchPoint mb;
  bool crossed = false;
  for (int k = 1; k <= n && !crossed; ++k) {
    b = k == n ? bottom : top + (bottom - top) * k / n;
    mb = ray.at(b);
    // The last step, at the far bound, crosses wherever it is reached: no value of the grid lies
    // beyond it (the GPU's division may round g there a hair below 0: sky would show the border).
    crossed = mb.p && (mb.g >= 0.0 || k == n);
    if (!crossed) a = b, ma = mb;
  }
  // No crossing only where even 1 km away the ray is not reached (an eye outside it); none
  // either where the ray comes no nearer the camera than 1/a: it passes outside the surface.
  if (!crossed || !ma.p) return std::nullopt;
  // Crossed between a (in front, g < 0) and b (at or behind): halve the bracket, then the point
  // where g, linear between its ends, is 0. Bisection, not false position: at a depth edge g
  // jumps, and false position creeps toward the jump from one side.
  double ga = ma.g, gb = mb.g;
  for (int s = 0; s < params.refine_steps; ++s) {
    const double c = 0.5 * (a + b);
    const MarchPoint mc = ray.at(c);
    if (!mc.p) break;  // cannot happen between two points the ray reaches; keep the bracket
    if (mc.g >= 0.0)
      b = c, gb = mc.g;
    else
      a = c, ga = mc.g;
  }
  return sphereProxyHit(1.0 / (a + ga * (b - a) / (ga - gb)), o, d);
}

}  // namespace telesphere::xr::render
