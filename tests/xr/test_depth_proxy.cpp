// SPDX-License-Identifier: MIT
/// @brief The depth proxies' geometry (xr/render/depth_proxy.h) against double-precision
///        references: a grid of one value is the sphere of that radius, also for eyes outside it;
///        a grid of a plane gives each eye ray the plane's own point, better with each step;
///        directions behind the camera and across the longitude seam; the centre-weighted radius
///        of a near object in and out of the centre; the nearest tile at a depth edge, bilinear
///        elsewhere; inverse depths of 0, NaN and of a point at the camera centre; tile sizes
///        that do not fit refused.
#include <gtest/gtest.h>

#include <cmath>
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
    for (double offset : {0.0, 0.05, 0.5 * r, 2.0 * r})  // 2r: the eye translated beyond the sphere
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d o = offset * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
        const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();  // any direction, behind included
        const auto want = render::sphereProxyHit(r_grid, o, d);
        const auto got = render::gridProxyHit(grid, o, d, 3);
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
  double worst_fixed = 0, worst[4] = {0, 0, 0, 0};
  for (double ax = -40; ax <= 40; ax += 5)
    for (double ay = -40; ay <= 40; ay += 5) {
      const Eigen::Vector3d d = Eigen::Vector3d(std::tan(ax * kDeg), std::tan(ay * kDeg), 1.0).normalized();
      const Eigen::Vector3d X = o + (D - o.z()) / d.z() * d;
      for (int steps = 0; steps < 4; ++steps) {
        const auto p = render::gridProxyHit(grid, o, d, steps);
        ASSERT_TRUE(p);
        worst[steps] = std::max(worst[steps], angleDeg(*p, X));
      }
      worst_fixed = std::max(worst_fixed, angleDeg(*render::sphereProxyHit(1.0, o, d), X));
    }
  // The fixed 1 m sphere is off by degrees here (γ ≈ 5 cm · (1/0.5 − 1) ≈ 2.9°); the grid's
  // first guess already much less, each step less again, three steps to the tiles' own error.
  EXPECT_GT(worst_fixed, 2.0);
  EXPECT_LT(worst[0], 1.0);
  EXPECT_LT(worst[1], worst[0]);
  EXPECT_LT(worst[2], worst[1]);
  // Measured: fixed 3.08°, steps 0–3: 0.22°, 0.012°, 0.00078°, 0.0004° (the 1° tiles' interpolation).
  EXPECT_LT(worst[3], 0.002) << "0 steps " << worst[0] << ", 1 " << worst[1] << ", 2 " << worst[2];
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

TEST(DepthProxy, AtADepthEdgeTheNearestOfTheFourTilesWinsAndElsewhereTheGridInterpolates) {
  // A wall 3 m away and a block at 0.5 m over the tiles within 8° of the axis in longitude (4°
  // tiles: centres at ±2°, ±6°; the next at ±10°) and 6° in latitude (centres at 0, ±4°; next ±8°).
  render::InverseDepthGrid grid(4.0);
  fill(grid, [](const Eigen::Vector3d& u) {
    const double lon = std::atan2(u.x(), u.z()) / kDeg, lat = std::asin(-u.y()) / kDeg;
    return std::abs(lon) < 8.0 && std::abs(lat) < 6.0 ? 2.0 : 1.0 / 3.0;
  });
  const double inf = std::numeric_limits<double>::infinity();
  // Between the block's last centre (6°) and the wall's first (10°): bilinear puts the edge at a
  // depth between (three quarters of the way to the wall at 9°); the nearest tile keeps the block.
  EXPECT_NEAR(grid.sample(lonLat(9.0, 0.0)), 0.25 * 2.0 + 0.75 / 3.0, 1e-6);
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(9.0, 0.0), 0.3), 2.0, 1e-6);
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(9.99, 7.99), 0.3), 2.0, 1e-6);  // the corner
  // A jump no larger than the threshold is interpolated; infinity is sample() everywhere.
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(9.0, 0.0), 2.0 - 1.0 / 3.0), grid.sample(lonLat(9.0, 0.0)), 1e-12);
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(10.01, 0.0), 0.3), 1.0 / 3.0, 1e-6);  // past the wall's centre
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(3.0, 4.0), 0.3), 2.0, 1e-6);          // inside the block
  std::mt19937 rng(35);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d d(n(rng), n(rng), n(rng));
    EXPECT_EQ(grid.sampleNearestAtEdges(d, inf), grid.sample(d));
    const double v = grid.sampleNearestAtEdges(d, 0.3);
    EXPECT_GE(v, grid.sample(d) - 1e-9);  // never farther than the interpolation
    EXPECT_TRUE(v == grid.sample(d) || std::abs(v - 2.0) < 1e-6);
  }
  // A slanted surface (inverse depth rising 0.1 1/m a tile along the longitude) interpolates.
  fill(grid, [](const Eigen::Vector3d& u) { return 1.0 + 0.025 * std::atan2(u.x(), u.z()) / kDeg; });
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d d(n(rng), n(rng), std::abs(n(rng)) + 0.5);
    EXPECT_EQ(grid.sampleNearestAtEdges(d, 0.3), grid.sample(d));
  }
}

TEST(DepthProxy, TheNearestTileAtAnEdgeFollowsTheSeamAndThePolesAsTheInterpolationDoes) {
  // At the extremes: across the longitude seam (straight behind, a lens wider than 180° sees
  // there) the tiles on both sides are neighbours; at a pole the rows clamp, as a texture with
  // clamp-to-edge does on the GPU, so a near row one tile off the pole does not reach it.
  render::InverseDepthGrid grid(5.0, 0.25F);
  grid.at(10, 0) = 4.0F;  // just east of the seam (longitude −180° to −175°)
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(178.0, -36.0), 0.3), 4.0, 1e-6);   // west of the seam
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(-178.0, -36.0), 0.3), 4.0, 1e-6);  // east of it
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(170.0, -36.0), 0.3), 0.25, 1e-6);  // a tile further west
  grid.at(1, 7) = 4.0F;  // the second row from the bottom pole
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(-142.0, -89.9), 0.3), 0.25, 1e-6);  // inside row 0's outer half
  EXPECT_NEAR(grid.sampleNearestAtEdges(lonLat(-142.0, -86.0), 0.3), 4.0, 1e-6);   // between rows 0 and 1
  EXPECT_TRUE(std::isfinite(grid.sampleNearestAtEdges({0, 1, 0}, 0.3)));
  EXPECT_TRUE(std::isfinite(grid.sampleNearestAtEdges({0, -1, 0}, 0.0)));
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
  const auto p = render::gridProxyHit(at_centre, {0.05, 0, 0}, {0, 0, 1}, 3);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->norm(), render::kMinProxyRadiusM, 1e-12);
  // The sky: a point 1 km out, the eye ray's own direction to 10⁻⁴ degrees.
  const render::InverseDepthGrid sky(10.0, 0.0F);
  const auto q = render::gridProxyHit(sky, {0.05, 0, 0}, {0, 0, 1}, 3);
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
