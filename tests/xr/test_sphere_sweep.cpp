// SPDX-License-Identifier: MIT
/// @brief The sphere sweep (xr/depth/sphere_sweep.h) against the true depth of synthetic scenes
///        rendered through the simulated 195° stereo rig: per-tile inverse-depth error bounds on a
///        textured room with a box 0.5 m ahead, both cameras as the reference; the AVX2 sums give
///        the scalar ones' result; a textureless room
///        leaves every tile unmatched (and says so) rather than guessing; images of the wrong size
///        match nothing. fillAndSmooth: holes take their neighbours' median, a lone outlier goes,
///        the longitude seam is no border.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "app/bench/prerendered_frames.h"
#include "calib/camera_resolution.h"
#include "robot/clock/clock.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/stereo/stereo_still.h"
#include "xr/depth/sphere_sweep.h"

namespace telesphere::xr {
namespace {

constexpr int kWidth = 480, kHeight = 270;

/// calib/data/sim_calibration.yaml's 4K lens at the sweep's size.
calib::CameraCalibration lens() { return bench::simulatedLens(kWidth, kHeight); }

const Eigen::Isometry3d kT_l_r(Eigen::Translation3d(0.064, 0.0, 0.0));  // right camera 64 mm to the right

/// A room around the left camera (walls 1–3 m away) and a 20 cm box whose face is 0.5 m ahead.
std::shared_ptr<robot::cameras::SyntheticScene> room(bool textured) {
  auto scene = std::make_shared<robot::cameras::SyntheticScene>();
  robot::cameras::SurfaceStyle style;
  style.pattern = textured;
  Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
  T_world_room.translation() = Eigen::Vector3d(0.0, -0.2, 1.0);
  scene->addRoom("room", T_world_room, Eigen::Vector3d(2.5, 1.4, 2.0), style, style, style, style);
  Eigen::Isometry3d T_world_box = Eigen::Isometry3d::Identity();
  T_world_box.translation() = Eigen::Vector3d(0.0, 0.0, 0.6);
  scene->addBox("box", robot::cameras::fixedPose(T_world_box), Eigen::Vector3d(0.1, 0.1, 0.1), style);
  return scene;
}

std::vector<std::uint8_t> grey(const std::shared_ptr<robot::cameras::SyntheticScene>& scene, const Eigen::Isometry3d& T_world_cam) {
  robot::clock::SteadyClock clock;
  robot::cameras::SyntheticCameraOptions options;
  options.supersampling = 2;
  const robot::cameras::SyntheticCamera camera(lens().camera, kWidth, kHeight, scene, robot::cameras::fixedPose(T_world_cam),
                                               clock, options);
  std::string out, error;
  EXPECT_TRUE(robot::stereo::toGray8(camera.renderAt(0), &out, &error)) << error;
  return {out.begin(), out.end()};
}

/// The true inverse depth toward a tile's centre from the camera at T_world_cam.
double trueInverseDepth(const robot::cameras::SyntheticScene& scene, const Eigen::Isometry3d& T_world_cam, const Eigen::Vector3d& d) {
  robot::cameras::SceneHit hit;
  return scene.view(0, T_world_cam).intersect(d, &hit) ? 1.0 / hit.distance : 0.0;
}

TEST(SphereSweep, FindsTheTrueInverseDepthOfATexturedRoomWithANearBoxFromEitherCamera) {
  const auto scene = room(true);
  const std::vector<std::uint8_t> left = grey(scene, Eigen::Isometry3d::Identity()), right = grey(scene, kT_l_r);
  const calib::CameraCalibration camera = lens();
  for (const bool left_reference : {true, false}) {
    SCOPED_TRACE(left_reference ? "left reference" : "right reference");
    const Eigen::Isometry3d T_other_reference = left_reference ? kT_l_r.inverse() : kT_l_r;
    const Eigen::Isometry3d T_world_reference = left_reference ? Eigen::Isometry3d::Identity() : kT_l_r;
    const depth::SphereSweep sweep(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, T_other_reference);
    const depth::GreyImage l{left.data(), kWidth, kHeight, kWidth}, r{right.data(), kWidth, kHeight, kWidth};
    const depth::SweepResult result = left_reference ? sweep.estimate(l, r) : sweep.estimate(r, l);
    ASSERT_GT(result.tiles_seen, 1000);  // a 195° lens sees more than half of the 4° tiles
    EXPECT_GT(result.tiles_matched, result.tiles_seen * 6 / 10) << result.tiles_matched << " of " << result.tiles_seen;
    // Every matched tile against the truth toward its centre: the 90th percentile within 0.1 1/m
    // (about 0.4° of disparity over 64 mm); tiles across the box's edges may be off, so no max.
    std::vector<double> errors;
    const render::InverseDepthGrid& grid = result.inverse_depth;
    for (int row = 0; row < grid.rows(); ++row)
      for (int col = 0; col < grid.cols(); ++col)
        if (result.confidence[static_cast<std::size_t>(row) * grid.cols() + col] > 0.0F)
          errors.push_back(std::abs(grid.at(row, col) - trueInverseDepth(*scene, T_world_reference, grid.tileCentre(row, col))));
    std::sort(errors.begin(), errors.end());
    ASSERT_FALSE(errors.empty());
    EXPECT_LT(errors[errors.size() / 2], 0.03) << "p50";
    EXPECT_LT(errors[errors.size() * 9 / 10], 0.1) << "p90";
    // The box straight ahead of the left camera (0.5 m: 2 1/m).
    const Eigen::Vector3d box = Eigen::Vector3d(0.0, 0.0, 0.5) - T_world_reference.translation();
    EXPECT_NEAR(grid.sample(box), 1.0 / box.norm(), 0.15);
  }
}

TEST(SphereSweep, EightSamplesAStepGiveTheOneAtATimeResult) {
  if (!depth::patchSumsSimdAvailable()) GTEST_SKIP() << "this CPU has no AVX2: the scalar sums are the only ones";
  const auto scene = room(true);
  const std::vector<std::uint8_t> left = grey(scene, Eigen::Isometry3d::Identity()), right = grey(scene, kT_l_r);
  const calib::CameraCalibration camera = lens();
  depth::SphereSweepOptions scalar_options;
  scalar_options.simd = false;
  const depth::SphereSweep simd(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse());
  const depth::SphereSweep scalar(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse(),
                                  scalar_options);
  const depth::GreyImage l{left.data(), kWidth, kHeight, kWidth}, r{right.data(), kWidth, kHeight, kWidth};
  const depth::SweepResult a = simd.estimate(l, r), b = scalar.estimate(l, r);
  // Each sample's grey value is the same integer bilinear; only the sums' float rounding order
  // differs, so a tile at a gate's edge may flip, nothing more.
  EXPECT_NEAR(a.tiles_matched, b.tiles_matched, 2);
  int both = 0;
  double worst = 0;
  for (int row = 0; row < a.inverse_depth.rows(); ++row)
    for (int col = 0; col < a.inverse_depth.cols(); ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * a.inverse_depth.cols() + col;
      if (a.confidence[i] <= 0.0F || b.confidence[i] <= 0.0F) continue;
      ++both;
      // Σb² − (Σb)²/n cancels in float (Σb² ≈ 4·10⁵ for 25 samples): ~10⁻⁴ either way.
      EXPECT_NEAR(a.confidence[i], b.confidence[i], 1e-3);
      worst = std::max(worst, double(std::abs(a.inverse_depth.at(row, col) - b.inverse_depth.at(row, col))));
    }
  EXPECT_GE(both, b.tiles_matched - 2);
  EXPECT_LT(worst, 1e-3) << "1/m";
}

TEST(SphereSweep, ATexturelessRoomMatchesNothingRatherThanGuessing) {
  const auto scene = room(false);
  const std::vector<std::uint8_t> left = grey(scene, Eigen::Isometry3d::Identity()), right = grey(scene, kT_l_r);
  const calib::CameraCalibration camera = lens();
  const depth::SphereSweep sweep(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse());
  const depth::SweepResult result =
      sweep.estimate({left.data(), kWidth, kHeight, kWidth}, {right.data(), kWidth, kHeight, kWidth});
  // Uniform faces give no texture; only tiles across the box's and walls' edges have any.
  EXPECT_LT(result.tiles_matched, result.tiles_seen / 10) << result.tiles_matched << " of " << result.tiles_seen;
}

TEST(SphereSweep, ImagesOfAnotherSizeMatchNothing) {
  const calib::CameraCalibration camera = lens();
  const depth::SphereSweep sweep(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse());
  std::vector<std::uint8_t> small(100 * 50, 128);
  const depth::SweepResult result = sweep.estimate({small.data(), 100, 50, 100}, {small.data(), 100, 50, 100});
  EXPECT_EQ(result.tiles_matched, 0);
  EXPECT_EQ(result.inverse_depth.sample({0, 0, 1}), 0.0);  // nothing known: the farthest hypothesis
  const depth::SweepResult none = sweep.estimate({}, {});
  EXPECT_EQ(none.tiles_matched, 0);
}

TEST(FillAndSmooth, HolesTakeTheirNeighboursAndALoneOutlierGoes) {
  render::InverseDepthGrid grid(10.0, 0.5F);  // 18 × 36 tiles
  std::vector<float> confidence(static_cast<std::size_t>(grid.rows()) * grid.cols(), 1.0F);
  const auto at = [&](int row, int col) -> float& { return confidence[static_cast<std::size_t>(row) * grid.cols() + col]; };
  // A hole of 3 × 3 unconfident tiles (their values junk) in a region of 2 1/m, across the seam.
  for (int row = 5; row <= 12; ++row)
    for (int col : {33, 34, 35, 0, 1, 2, 3})
      grid.at(row, col) = 2.0F;
  for (int row = 8; row <= 10; ++row)
    for (int col : {35, 0, 1}) {
      grid.at(row, col) = 99.0F;
      at(row, col) = 0.0F;
    }
  // A lone outlier elsewhere.
  grid.at(3, 18) = 7.0F;
  depth::fillAndSmooth(grid, confidence);
  for (int row = 8; row <= 10; ++row)
    for (int col : {35, 0, 1}) EXPECT_FLOAT_EQ(grid.at(row, col), 2.0F) << row << "," << col;
  EXPECT_FLOAT_EQ(grid.at(3, 18), 0.5F);
  EXPECT_FLOAT_EQ(grid.at(0, 0), 0.5F);
}

}  // namespace
}  // namespace telesphere::xr
