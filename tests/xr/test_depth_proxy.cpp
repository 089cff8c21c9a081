// SPDX-License-Identifier: MIT
/// @brief The depth proxies' geometry (xr/render/depth_proxy.h) against double-precision
///        references: a grid of one value is the sphere of that radius, also for eyes outside it;
///        a grid of a plane gives each eye ray the plane's own point, better with each step;
///        directions behind the camera and across the longitude seam; the centre-weighted radius
///        of a near object in and out of the centre; the closest tile at a depth edge (or the
///        nearest depth), bilinear elsewhere; the march to each eye ray's first crossing against a
///        brute-force one; inverse depths of 0, NaN and of a point at the camera centre; tile
///        sizes that do not fit refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

#include "xr/render/depth_proxy.h"

namespace telesphere::xr {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDeg;
}

/// Every tile of `grid` set to f(tile centre direction).
template <typename F>
void fill(render::InverseDepthGrid& grid, F f) {
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) grid.at(row, col) = static_cast<float>(f(grid.tileCentre(row, col)));
}

TEST(DepthProxy, AGridOfOneValueIsTheSphereOfThatRadiusForEyesInsideAndOutsideIt) {
  std::mt19937 rng(35);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double r : {0.3, 1.0, 7.0}) {
    const render::InverseDepthGrid grid(4.0, static_cast<float>(1.0 / r));
    const double r_grid = 1.0 / static_cast<float>(1.0 / r);  // the float the grid holds
    const render::GridProxyParams params = render::gridProxyParams(grid);
    for (double offset : {0.0, 0.05, 0.5 * r, 2.0 * r})  // 2r: the eye translated beyond the sphere
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d o = offset * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
        const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();  // any direction, behind included
        const auto want = render::sphereProxyHit(r_grid, o, d);
        const auto got = render::gridProxyHit(grid, params, o, d);
        ASSERT_EQ(got.has_value(), want.has_value()) << "r " << r << " offset " << offset;
        if (want) {
          EXPECT_LT((*got - *want).norm(), 1e-9 * r) << "r " << r << " offset " << offset;
          EXPECT_NEAR(got->norm(), r_grid, 1e-9 * r);
        }
      }
  }
}

TEST(DepthProxy, AGridOfAPlaneShowsEachEyeRayThePlanesOwnPointBetterWithEachStep) {
  // The plane z = D in front of the camera; behind and beside it the grid holds 0 (far away).
  // An eye 5 cm beside the camera looks at it: the true point X is where its ray meets the plane,
  // and the camera shows X exactly when the proxy point lies on the camera's ray through X.
  const double D = 0.5;
  render::InverseDepthGrid grid(1.0);
  fill(grid, [&](const Eigen::Vector3d& u) { return u.z() > 0.05 ? u.z() / D : 0.0; });
  const Eigen::Vector3d o(0.05, -0.02, 0.0);
  const double inf = std::numeric_limits<double>::infinity();
  double worst_fixed = 0, worst_march[4] = {0, 0, 0, 0}, worst_fixed_point[4] = {0, 0, 0, 0};
  for (double ax = -40; ax <= 40; ax += 5)
    for (double ay = -40; ay <= 40; ay += 5) {
      const Eigen::Vector3d d = Eigen::Vector3d(std::tan(ax * kDeg), std::tan(ay * kDeg), 1.0).normalized();
      const Eigen::Vector3d X = o + (D - o.z()) / d.z() * d;
      for (int steps = 0; steps < 4; ++steps) {
        const auto p = render::gridProxyHit(grid, render::gridProxyParams(grid, render::kGridEdgeSlopePerMPerDeg,
                                                                          render::kGridMarchStepTiles, steps), o, d);
        const auto q = render::gridProxyHit(grid, render::gridProxyParams(grid, render::kGridEdgeSlopePerMPerDeg, inf, steps), o, d);
        ASSERT_TRUE(p && q);
        worst_march[steps] = std::max(worst_march[steps], angleDeg(*p, X));
        worst_fixed_point[steps] = std::max(worst_fixed_point[steps], angleDeg(*q, X));
      }
      worst_fixed = std::max(worst_fixed, angleDeg(*render::sphereProxyHit(1.0, o, d), X));
    }
  // The fixed 1 m sphere is off by degrees here (γ ≈ 5 cm · (1/0.5 − 1) ≈ 2.9°). Without the march
  // the grid's first guess is already much less, each fixed-point step less again, three steps to
  // the tiles' own error. The march brackets the plane within a step of 1/2 tile and takes it as
  // linear there, so its first guess is there already; bisecting first never makes it worse.
  EXPECT_GT(worst_fixed, 2.0);
  EXPECT_LT(worst_fixed_point[0], 1.0);
  EXPECT_LT(worst_fixed_point[1], worst_fixed_point[0]);
  EXPECT_LT(worst_fixed_point[2], worst_fixed_point[1]);
  // Measured: fixed 3.08°, fixed-point steps 0–3: 0.22°, 0.012°, 0.00078°, 0.0004° (the 1° tiles' interpolation).
  EXPECT_LT(worst_fixed_point[3], 0.002) << "0 steps " << worst_fixed_point[0] << ", 1 " << worst_fixed_point[1] << ", 2 "
                                         << worst_fixed_point[2];
  for (int steps = 1; steps < 4; ++steps) EXPECT_LE(worst_march[steps], worst_march[steps - 1] + 1e-6) << steps;
  EXPECT_LT(worst_march[3], 0.002) << "0 steps " << worst_march[0] << ", 1 " << worst_march[1] << ", 2 " << worst_march[2];
}

/// The first crossing of the ray o + t·d with the surface |p| = 1/grid(p) by brute force: the far
/// root at 2000 inverse depths from the top of the grid down, then 60 bisections of the first
/// step that crossed. Also says whether the grid jumps there (a depth edge: the crossing is the
/// outline, not a surface).
struct Crossing {
  std::optional<Eigen::Vector3d> p;
  bool at_edge = false;
};

Crossing bruteForceCrossing(const render::InverseDepthGrid& grid, const render::GridProxyParams& params, const Eigen::Vector3d& o,
                            const Eigen::Vector3d& d) {
  const auto g = [&](double rho, Eigen::Vector3d* p) -> std::optional<double> {
    const auto q = render::sphereProxyHit(1.0 / rho, o, d);
    if (!q) return std::nullopt;
    if (p) *p = *q;
    return 1.0 / render::radiusFromInverseDepth(grid.sampleKeepingEdges(*q, params.edge_jump_per_m, params.edge_tile)) - rho;
  };
  const double top = params.inverse_depth_top_per_m, bottom = params.inverse_depth_bottom_per_m;
  constexpr int kSteps = 2000;
  double a = top;
  for (int k = 0; k <= kSteps; ++k) {
    const double b = top + (bottom - top) * k / kSteps;
    const auto gb = g(b, nullptr);
    if (gb && *gb >= 0.0) {
      if (k == 0) return {render::sphereProxyHit(1.0 / b, o, d), false};
      double lo = b, hi = a;  // g(lo) >= 0, g(hi) < 0
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        const auto gm = g(mid, nullptr);
        (gm && *gm >= 0.0 ? lo : hi) = mid;
      }
      Eigen::Vector3d p_lo, p_hi;
      g(lo, &p_lo);
      const bool reached = g(hi, &p_hi).has_value();
      const bool edge = reached && std::abs(grid.sampleKeepingEdges(p_lo, params.edge_jump_per_m, params.edge_tile) -
                                            grid.sampleKeepingEdges(p_hi, params.edge_jump_per_m, params.edge_tile)) > 1e-3;
      return {render::sphereProxyHit(1.0 / lo, o, d), edge};
    }
    a = b;
  }
  return {};
}

TEST(DepthProxy, EachEyeRayMeetsTheGridWhereItFirstCrossesItAlsoBeyondANearObjectsEdge) {
  // A wall 3 m around the camera, a box 0.35 m ahead over the tiles within 12° of the axis (4°
  // tiles), and a floor rising toward the camera below it (a smooth slope). An eye 3–10 cm from
  // the camera sees the box's edge where its own ray's direction lies beyond the box: fixed-point
  // steps from that direction settle on the wall (the box's outline retracts), the march finds
  // the box's tiles first, as the brute-force first crossing does.
  render::InverseDepthGrid grid(4.0);
  fill(grid, [](const Eigen::Vector3d& u) {
    if (u.z() > std::cos(12.0 * kDeg)) return 1.0 / 0.35;
    if (u.y() > 0.3) return 1.0 / 3.0 + 2.0 * (u.y() - 0.3);  // the floor below
    return 1.0 / 3.0;
  });
  const render::GridProxyParams march = render::gridProxyParams(grid);
  EXPECT_NEAR(march.inverse_depth_top_per_m, static_cast<float>(1.0 / 0.35), 1e-9);  // the box, the grid's largest
  const render::GridProxyParams fixed_point =
      render::gridProxyParams(grid, render::kGridEdgeSlopePerMPerDeg, std::numeric_limits<double>::infinity());
  std::vector<double> surface, edge;  // degrees between the march's point and the first crossing, as the camera sees them
  int fixed_point_off = 0, most_reads = 0;
  for (const double offset : {0.03, 0.06, 0.1})
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d o = offset * Eigen::Vector3d(std::cos(k * kDeg * 45), std::sin(k * kDeg * 45), 0.2 * (k % 3 - 1)).normalized();
      for (double ax = -40; ax <= 40; ax += 1.7)
        for (double ay = -40; ay <= 40; ay += 3.3) {
          const Eigen::Vector3d d = Eigen::Vector3d(std::tan(ax * kDeg), std::tan(ay * kDeg), 1.0).normalized();
          const Crossing want = bruteForceCrossing(grid, march, o, d);
          ASSERT_TRUE(want.p);
          int reads = 0;
          const auto got = render::gridProxyHit(grid, march, o, d, &reads);
          ASSERT_TRUE(got);
          most_reads = std::max(most_reads, reads);
          (want.at_edge ? edge : surface).push_back(angleDeg(*got, *want.p));
          const auto old = render::gridProxyHit(grid, fixed_point, o, d);
          if (old && angleDeg(*old, *want.p) > 1.0) ++fixed_point_off;
        }
    }
  const auto fraction_above = [](const std::vector<double>& v, double limit) {
    return static_cast<double>(std::count_if(v.begin(), v.end(), [&](double e) { return e > limit; })) / static_cast<double>(v.size());
  };
  const double surface_worst = *std::max_element(surface.begin(), surface.end());
  // On a surface the march lands on the crossing. The last step takes g as linear between the
  // bracket's ends, so where the bracket also holds a jump or the floor's kink it is up to a
  // tenth of a degree off (0.15 % of the rays more than 0.001°, the worst 0.083°). At an outline it lands within a
  // small part of a tile, except where the ray's path clips a corner of the box's tiles within one
  // march step and the march steps over it (2.4 % of the rays at an edge, several degrees off:
  // they show the wall beside the box's corner).
  EXPECT_LT(fraction_above(surface, 1e-3), 0.01) << surface.size() << " rays on a surface";
  EXPECT_LT(surface_worst, 0.2);
  EXPECT_GT(edge.size(), 200U);
  EXPECT_LT(fraction_above(edge, 0.5), 0.04) << edge.size() << " rays at an edge";
  // Reads stay bounded: the first, the march's steps for an eye 10 cm away (the angle it sweeps
  // over half a tile), the bisections.
  const int most_steps = static_cast<int>(std::ceil(0.1 * (march.inverse_depth_top_per_m - march.inverse_depth_bottom_per_m) /
                                                    march.march_step_rad));
  EXPECT_LE(most_reads, 1 + most_steps + render::kGridProxySteps);
  // The fixed-point steps put hundreds of these rays on the wall behind the box's edge (1615; the
  // test would otherwise pass without the march).
  EXPECT_GT(fixed_point_off, 200);
  std::printf("first crossing: %zu rays on a surface (%.2g %% more than 0.001 deg off, worst %.2g deg), %zu at an edge "
              "(%.2g %% more than 0.5 deg off); %d reads at most; fixed-point steps more than 1 deg off on %d\n",
              surface.size(), 100 * fraction_above(surface, 1e-3), surface_worst, edge.size(), 100 * fraction_above(edge, 0.5),
              most_reads, fixed_point_off);
}

TEST(DepthProxy, DirectionsBehindTheCameraAndAcrossTheLongitudeSeamAreCovered) {
  render::InverseDepthGrid grid(5.0);
  // Near behind the camera (a lens wider than 180° sees there), far in front.
  fill(grid, [](const Eigen::Vector3d& u) { return u.z() < 0.0 ? 2.0 : 0.25; });
  EXPECT_NEAR(grid.sample({0, 0, 1}), 0.25, 1e-6);
  EXPECT_NEAR(grid.sample({0, 0, -1}), 2.0, 1e-6);
  EXPECT_NEAR(grid.sample({0.3, 0.1, -1}), 2.0, 1e-6);
  // Straight behind is longitude ±180°: both sides of the seam give the same value.
  const double left = grid.sample({-1e-6, 0.2, -1}), right = grid.sample({1e-6, 0.2, -1});
  EXPECT_NEAR(left, right, 1e-6);
  // The poles (straight up and down in the camera frame) are defined.
  EXPECT_TRUE(std::isfinite(grid.sample({0, -1, 0})));
  EXPECT_TRUE(std::isfinite(grid.sample({0, 1, 0})));
  // Tile centres round-trip through sample().
  for (int row = 0; row < grid.rows(); row += 7)
    for (int col = 0; col < grid.cols(); col += 5) {
      grid.at(row, col) = 5.0F + static_cast<float>(row + col);
      EXPECT_NEAR(grid.sample(grid.tileCentre(row, col)), grid.at(row, col), 1e-4) << row << "," << col;
      grid.at(row, col) = 0.25F;
    }
}

/// The direction at longitude and latitude (degrees) in the grid's convention.
Eigen::Vector3d lonLat(double lon_deg, double lat_deg) {
  const double lon = lon_deg * kDeg, lat = lat_deg * kDeg;
  return {std::cos(lat) * std::sin(lon), -std::sin(lat), std::cos(lat) * std::cos(lon)};
}

TEST(DepthProxy, AtADepthEdgeTheClosestOfTheFourTilesWinsAndElsewhereTheGridInterpolates) {
  // A wall 3 m away and a block at 0.5 m over the tiles within 8° of the axis in longitude (4°
  // tiles: centres at ±2°, ±6°; the next at ±10°) and 6° in latitude (centres at 0, ±4°; next ±8°).
  render::InverseDepthGrid grid(4.0);
  fill(grid, [](const Eigen::Vector3d& u) {
    const double lon = std::atan2(u.x(), u.z()) / kDeg, lat = std::asin(-u.y()) / kDeg;
    return std::abs(lon) < 8.0 && std::abs(lat) < 6.0 ? 2.0 : 1.0 / 3.0;
  });
  const double inf = std::numeric_limits<double>::infinity();
  constexpr auto kNearestDepth = render::GridEdgeTile::kNearestDepth;
  // Between the block's last centre (6°) and the wall's first (10°): bilinear puts the edge at a
  // depth between (three quarters of the way to the wall at 9°); the closest tile puts the outline
  // halfway, at 8°: the block up to it, the wall beyond. The nearest depth keeps the block a tile out.
  EXPECT_NEAR(grid.sample(lonLat(9.0, 0.0)), 0.25 * 2.0 + 0.75 / 3.0, 1e-6);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(7.9, 0.0), 0.3), 2.0, 1e-6);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(8.1, 0.0), 0.3), 1.0 / 3.0, 1e-6);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(7.9, 5.9), 0.3), 2.0, 1e-6);  // inside the corner
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(7.9, 6.1), 0.3), 1.0 / 3.0, 1e-6);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(9.0, 0.0), 0.3, kNearestDepth), 2.0, 1e-6);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(9.99, 7.99), 0.3, kNearestDepth), 2.0, 1e-6);  // the corner
  // A jump no larger than the threshold is interpolated; infinity is sample() everywhere.
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(9.0, 0.0), 2.0 - 1.0 / 3.0), grid.sample(lonLat(9.0, 0.0)), 1e-12);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(10.01, 0.0), 0.3), 1.0 / 3.0, 1e-6);  // past the wall's centre
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(3.0, 4.0), 0.3), 2.0, 1e-6);          // inside the block
  std::mt19937 rng(35);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d d(n(rng), n(rng), n(rng));
    EXPECT_EQ(grid.sampleKeepingEdges(d, inf), grid.sample(d));
    EXPECT_EQ(grid.sampleKeepingEdges(d, inf, kNearestDepth), grid.sample(d));
    const double v = grid.sampleKeepingEdges(d, 0.3);
    EXPECT_TRUE(v == grid.sample(d) || std::abs(v - 2.0) < 1e-6 || std::abs(v - 1.0 / 3.0) < 1e-6) << v;
    const double nearest = grid.sampleKeepingEdges(d, 0.3, kNearestDepth);
    EXPECT_GE(nearest, grid.sample(d) - 1e-9);  // never farther than the interpolation
    EXPECT_GE(nearest, v - 1e-9);
    EXPECT_TRUE(nearest == grid.sample(d) || std::abs(nearest - 2.0) < 1e-6);
  }
  // A slanted surface (inverse depth rising 0.1 1/m a tile along the longitude) interpolates.
  fill(grid, [](const Eigen::Vector3d& u) { return 1.0 + 0.025 * std::atan2(u.x(), u.z()) / kDeg; });
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d d(n(rng), n(rng), std::abs(n(rng)) + 0.5);
    EXPECT_EQ(grid.sampleKeepingEdges(d, 0.3), grid.sample(d));
  }
}

TEST(DepthProxy, TheTileAtAnEdgeFollowsTheSeamAndThePolesAsTheInterpolationDoes) {
  // At the extremes: across the longitude seam (straight behind, a lens wider than 180° sees
  // there) the tiles on both sides are neighbours; at a pole the rows clamp, as a texture with
  // clamp-to-edge does on the GPU, so a near row one tile off the pole does not reach it.
  constexpr auto kNearestDepth = render::GridEdgeTile::kNearestDepth;
  render::InverseDepthGrid grid(5.0, 0.25F);
  grid.at(10, 0) = 4.0F;  // just east of the seam (longitude −180° to −175°)
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(178.0, -36.0), 0.3, kNearestDepth), 4.0, 1e-6);  // west of the seam
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(178.0, -36.0), 0.3), 0.25, 1e-6);  // the closest: west's own tile
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(-179.0, -36.0), 0.3), 4.0, 1e-6);  // east of it, from the quad across it
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(-178.0, -36.0), 0.3), 4.0, 1e-6);
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(170.0, -36.0), 0.3, kNearestDepth), 0.25, 1e-6);  // a tile further west
  grid.at(1, 7) = 4.0F;  // the second row from the bottom pole
  for (const auto tile : {render::GridEdgeTile::kClosest, kNearestDepth})
    EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(-142.0, -89.9), 0.3, tile), 0.25, 1e-6);  // inside row 0's outer half
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(-142.0, -86.0), 0.3, kNearestDepth), 4.0, 1e-6);  // between rows 0 and 1
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(-142.0, -86.0), 0.3), 0.25, 1e-6);                // nearer row 0's centre
  EXPECT_NEAR(grid.sampleKeepingEdges(lonLat(-142.0, -84.0), 0.3), 4.0, 1e-6);                 // nearer row 1's
  EXPECT_TRUE(std::isfinite(grid.sampleKeepingEdges({0, 1, 0}, 0.3)));
  EXPECT_TRUE(std::isfinite(grid.sampleKeepingEdges({0, -1, 0}, 0.0)));
}

TEST(DepthProxy, TheCentreWeightedRadiusFollowsANearObjectOnlyWhileItIsInTheCentre) {
  const auto scene = [](double object_deg) {
    render::InverseDepthGrid grid(2.0);
    const Eigen::Vector3d object(std::sin(object_deg * kDeg), 0.0, std::cos(object_deg * kDeg));
    fill(grid, [&](const Eigen::Vector3d& u) { return angleDeg(u, object) < 12.0 ? 1.0 / 0.4 : 1.0 / 3.0; });
    return grid;
  };
  const Eigen::Vector3d ahead(0, 0, 1);
  EXPECT_NEAR(render::centreWeightedRadius(scene(0.0), ahead, 10.0 * kDeg), 0.4, 1e-6);
  EXPECT_NEAR(render::centreWeightedRadius(scene(35.0), ahead, 10.0 * kDeg), 3.0, 1e-5);
  // With the whole sphere weighted alike the background wins even with the object ahead.
  EXPECT_NEAR(render::centreWeightedRadius(scene(0.0), ahead, 1000.0), 3.0, 1e-5);
  // The gaze on the object: its radius again.
  EXPECT_NEAR(render::centreWeightedRadius(scene(35.0), {std::sin(35 * kDeg), 0, std::cos(35 * kDeg)}, 10.0 * kDeg),
              0.4, 1e-6);
}

TEST(DepthProxy, InverseDepthsAtTheExtremesGiveBoundedRadii) {
  EXPECT_EQ(render::radiusFromInverseDepth(0.0), render::kMaxProxyRadiusM);  // the sky
  EXPECT_EQ(render::radiusFromInverseDepth(-1.0), render::kMaxProxyRadiusM);
  EXPECT_EQ(render::radiusFromInverseDepth(std::numeric_limits<double>::quiet_NaN()), render::kMaxProxyRadiusM);
  EXPECT_EQ(render::radiusFromInverseDepth(std::numeric_limits<double>::infinity()), render::kMinProxyRadiusM);  // at the centre
  EXPECT_EQ(render::radiusFromInverseDepth(1e9), render::kMinProxyRadiusM);
  EXPECT_DOUBLE_EQ(render::radiusFromInverseDepth(0.5), 2.0);
  // A grid of points at the camera centre and an eye 5 cm away: a point on the 0.1 m sphere.
  const render::InverseDepthGrid at_centre(10.0, std::numeric_limits<float>::infinity());
  const auto p = render::gridProxyHit(at_centre, render::gridProxyParams(at_centre), {0.05, 0, 0}, {0, 0, 1});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->norm(), render::kMinProxyRadiusM, 1e-12);
  // Where the march starts: the largest value, NaN left out, infinity (a point at the centre)
  // bounded to the nearest radius; a grid of sky starts and ends at the far bound.
  render::InverseDepthGrid odd(10.0, 0.5F);
  odd.at(3, 4) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_DOUBLE_EQ(render::gridProxyParams(odd).inverse_depth_top_per_m, 0.5);
  odd.at(5, 6) = std::numeric_limits<float>::infinity();
  EXPECT_DOUBLE_EQ(render::gridProxyParams(odd).inverse_depth_top_per_m, 1.0 / render::kMinProxyRadiusM);
  EXPECT_DOUBLE_EQ(render::gridProxyParams(render::InverseDepthGrid(10.0, 0.0F)).inverse_depth_top_per_m,
                   1.0 / render::kMaxProxyRadiusM);
  // The sky: a point 1 km out, the eye ray's own direction to 10⁻⁴ degrees.
  const render::InverseDepthGrid sky(10.0, 0.0F);
  const auto q = render::gridProxyHit(sky, render::gridProxyParams(sky), {0.05, 0, 0}, {0, 0, 1});
  ASSERT_TRUE(q);
  EXPECT_LT(angleDeg(*q, {0, 0, 1}), 0.05 / 1000 / kDeg * 1.01);
}

TEST(DepthProxy, TileSizesThatDoNotDivideTheSphereAreRefused) {
  for (double bad : {0.0, -4.0, 7.0, 100.0, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_THROW(render::InverseDepthGrid grid(bad), std::invalid_argument) << bad;
  const render::InverseDepthGrid grid(4.0);
  EXPECT_EQ(grid.rows(), 45);
  EXPECT_EQ(grid.cols(), 90);
}

}  // namespace
}  // namespace telesphere::xr
