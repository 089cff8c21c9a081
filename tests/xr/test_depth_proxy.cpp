// SPDX-License-Identifier: MIT
/// @brief The depth proxies' geometry (xr/render/depth_proxy.h) against double-precision
///        references: a grid of one value is the sphere of that radius, also for eyes outside it;
///        a grid of a plane gives each eye ray the plane's own point, better with each step;
///        directions behind the camera and across the longitude seam; the centre-weighted radius
///        of a near object in and out of the centre; inverse depths of 0, NaN and of a point at
///        the camera centre; tile sizes that do not fit refused.
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
