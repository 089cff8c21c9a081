// SPDX-License-Identifier: MIT
/// @brief The sphere sweep (xr/depth/sphere_sweep.h) against the true depth of synthetic scenes
///        rendered through the simulated 195° stereo rig: per-tile inverse-depth error bounds on a
///        textured room with a box 0.5 m ahead, both cameras as the reference; the AVX2 sums give
///        the scalar ones' result; a textureless room
///        leaves every tile unmatched (and says so) rather than guessing; images of the wrong size
///        match nothing. A board of stripes that the pair alone leaves
///        ambiguous is decided by an earlier view from the arm's motion, and neither a motion
///        along the stripes nor a board that moved between the captures makes a wrong tile confident.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include <sys/mman.h>

#include "app/bench/prerendered_frames.h"
#include "robot/cameras/synthetic_scene.h"
#include "tests/xr/scene_grey.h"
#include "tests/xr/stripes_room.h"
#include "xr/depth/sphere_sweep.h"

namespace telesphere::xr {
namespace {

constexpr int kWidth = 480, kHeight = 270;

/// calib/data/sim_calibration.yaml's 4K lens at the sweep's size.
calib::CameraCalibration lens() { return bench::simulatedLens(kWidth, kHeight); }

const Eigen::Isometry3d kT_l_r(Eigen::Translation3d(0.064, 0.0, 0.0));  // right camera 64 mm to the right

/// A room around the left camera (walls 1–3 m away) and a 20 cm box whose face is 0.5 m ahead.
std::shared_ptr<robot::cameras::SyntheticScene> room(bool textured) {
  auto scene = test_scenes::room(textured);
  robot::cameras::SurfaceStyle style;
  style.pattern = textured;
  Eigen::Isometry3d T_world_box = Eigen::Isometry3d::Identity();
  T_world_box.translation() = Eigen::Vector3d(0.0, 0.0, 0.6);
  scene->addBox("box", robot::cameras::fixedPose(T_world_box), Eigen::Vector3d(0.1, 0.1, 0.1), style);
  return scene;
}

std::vector<std::uint8_t> grey(const std::shared_ptr<robot::cameras::SyntheticScene>& scene, const Eigen::Isometry3d& T_world_cam) {
  return test_scenes::greyImage(scene, lens().camera, kWidth, kHeight, T_world_cam);
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

/// The room without the box and, with `board`, 0.8 m ahead a 1.2 × 0.8 m board of vertical stripes
/// 2 cm apart (1.4° there, a third of the pair's disparity): it matches at several depths along the
/// baseline.
std::shared_ptr<robot::cameras::SyntheticScene> stripesRoom(bool board = true) {
  auto scene = test_scenes::room(true);
  if (board) test_scenes::addStripesBoard(*scene, {0.0, 0.0, 0.8});
  return scene;
}

/// The board's inner tiles (those whose eight neighbours' centres all meet the board too: a tile at
/// its edge, half wall, has no one true depth): how many, how many the sweep matched, how many of
/// those lie more than 0.1 1/m from the truth toward the tile's centre (a pattern's aliases lie
/// 0.37 1/m apart), and how many of all lie within it (matched or filled).
struct BoardScore {
  int inner = 0, matched = 0, matched_wrong = 0, right = 0;
};

BoardScore scoreBoard(const depth::SweepResult& result, const robot::cameras::SyntheticScene& board_scene) {
  BoardScore score;
  const render::InverseDepthGrid& grid = result.inverse_depth;
  const robot::cameras::SceneView view = board_scene.view(0, Eigen::Isometry3d::Identity());
  const auto onBoard = [&](int row, int col) {
    robot::cameras::SceneHit hit;
    return view.intersect(grid.tileCentre(row, (col + grid.cols()) % grid.cols()), &hit) && hit.object == 1;
  };
  for (int row = 1; row + 1 < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      bool inner = true;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) inner = inner && onBoard(row + dr, col + dc);
      if (!inner) continue;
      const double error = std::abs(grid.at(row, col) - trueInverseDepth(board_scene, Eigen::Isometry3d::Identity(), grid.tileCentre(row, col)));
      const bool matched = result.confidence[static_cast<std::size_t>(row) * grid.cols() + col] > 0.0F;
      ++score.inner;
      score.matched += matched;
      score.matched_wrong += matched && error >= 0.1;
      score.right += error < 0.1;
    }
  return score;
}

/// The left camera's image from `p_world_cam` (no rotation) as an earlier view for the left camera at the origin.
struct EarlierCapture {
  std::vector<std::uint8_t> grey;
  depth::EarlierView view;
};
EarlierCapture earlierCapture(const std::shared_ptr<robot::cameras::SyntheticScene>& scene, const Eigen::Vector3d& p_world_cam) {
  const Eigen::Isometry3d T_world_earlier{Eigen::Translation3d(p_world_cam)};
  EarlierCapture capture{grey(scene, T_world_earlier), {}};
  capture.view = {{capture.grey.data(), kWidth, kHeight, kWidth}, T_world_earlier.inverse()};
  return capture;
}

TEST(SphereSweep, EarlierViewsFromTheArmsMotionDecideAPatternThePairLeavesAmbiguous) {
  const auto scene = stripesRoom();
  const std::vector<std::uint8_t> left = grey(scene, Eigen::Isometry3d::Identity()), right = grey(scene, kT_l_r);
  const calib::CameraCalibration camera = lens();
  const depth::SphereSweep sweep(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse());
  const depth::GreyImage l{left.data(), kWidth, kHeight, kWidth}, r{right.data(), kWidth, kHeight, kWidth};

  const depth::SweepResult pair_only = sweep.estimate(l, r);
  const BoardScore before = scoreBoard(pair_only, *scene);
  ASSERT_GT(before.inner, 100);  // the board spans about 74° × 53°
  EXPECT_GT(pair_only.tiles_ambiguous, before.inner / 2);
  EXPECT_EQ(pair_only.tiles_decided_by_motion, 0);
  // The pair alone: most of the board is left unconfident and filled from the wall behind, and
  // some tiles take an alias with confidence (its hypothesis hit the alias's peak, none the truth's).
  EXPECT_LT(before.right, before.inner / 2) << before.right << " of " << before.inner;

  // Earlier the arm held the camera 5 cm and 1 cm to the left (and 1 cm lower): two more baselines
  // along the pattern's direction of change, whose aliases fall elsewhere (the longest first).
  const EarlierCapture near = earlierCapture(scene, {-0.01, 0.01, 0.0}), far = earlierCapture(scene, {-0.05, 0.01, 0.0});
  const depth::SweepResult with_motion = sweep.estimate(l, r, {far.view, near.view});
  const BoardScore after = scoreBoard(with_motion, *scene);
  EXPECT_EQ(with_motion.tiles_ambiguous, pair_only.tiles_ambiguous);
  EXPECT_GT(with_motion.tiles_decided_by_motion, before.inner * 3 / 4);
  EXPECT_GT(after.right, after.inner * 95 / 100) << after.right << " of " << after.inner;
  EXPECT_LE(after.matched_wrong, 2) << after.matched_wrong << " of " << after.matched << " matched";

  // A motion along the stripes sees all their candidates alike: on the board it decides nothing,
  // and the board's tiles are the pair's own (the textured walls it does decide).
  const EarlierCapture below = earlierCapture(scene, {0.0, 0.03, 0.0});
  const BoardScore along = scoreBoard(sweep.estimate(l, r, {below.view}), *scene);
  EXPECT_EQ(along.matched, before.matched);
  EXPECT_EQ(along.matched_wrong, before.matched_wrong);

  // Earlier the board was not there: its patches find nothing alike in those views, so they
  // decide nothing on it either.
  const auto empty_room = stripesRoom(false);
  const EarlierCapture near_empty = earlierCapture(empty_room, {-0.01, 0.01, 0.0}), far_empty = earlierCapture(empty_room, {-0.05, 0.01, 0.0});
  const BoardScore changed = scoreBoard(sweep.estimate(l, r, {far_empty.view, near_empty.view}), *scene);
  EXPECT_LE(changed.matched_wrong, before.matched_wrong) << changed.matched_wrong << " of " << changed.matched << " matched";

  // Views of another size are ignored.
  const std::vector<std::uint8_t> small(kWidth / 2 * kHeight / 2, 128);
  const depth::SweepResult ignored = sweep.estimate(l, r, {{{small.data(), kWidth / 2, kHeight / 2, kWidth / 2}, far.view.T_earlier_reference}});
  EXPECT_EQ(ignored.tiles_decided_by_motion, 0);
  EXPECT_EQ(ignored.tiles_matched, pair_only.tiles_matched);
}

TEST(SphereSweep, ImagesSpanningOverTwoGigabytesGiveTheOneAtATimeGridOfThePackedImages) {
  // Images inside a larger buffer (a row of each every `stride` bytes) whose last rows lie beyond
  // 2^31 bytes from their first pixel: the eight-a-step sums address pixels by 32-bit offsets, so
  // they must not be used there (their offsets wrapped and read 2 GiB away). Spread out, the pair
  // and its earlier views must give the grid of the one-at-a-time sums on the packed images, to the
  // bit. One mapping holds the four spread images side by side; only the pages with pixels are
  // ever touched (~2 MB).
  const auto scene = stripesRoom();
  const std::vector<std::uint8_t> left = grey(scene, Eigen::Isometry3d::Identity()), right = grey(scene, kT_l_r);
  const EarlierCapture near = earlierCapture(scene, {-0.01, 0.01, 0.0}), far = earlierCapture(scene, {-0.05, 0.01, 0.0});
  const std::size_t stride = (std::size_t{1} << 31) / (kHeight - 40);  // row 230 lies past 2^31
  const std::size_t bytes = stride * kHeight;
  void* mapped = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (mapped == MAP_FAILED) GTEST_SKIP() << "no " << bytes / 1e9 << " GB of address space to map here";
  std::uint8_t* spread = static_cast<std::uint8_t*>(mapped);
  const std::vector<const std::vector<std::uint8_t>*> packed = {&left, &right, &near.grey, &far.grey};
  for (std::size_t k = 0; k < packed.size(); ++k)
    for (int y = 0; y < kHeight; ++y)
      std::copy_n(packed[k]->data() + static_cast<std::size_t>(y) * kWidth, kWidth, spread + y * stride + k * kWidth);
  const auto at = [&](std::size_t k) { return depth::GreyImage{spread + k * kWidth, kWidth, kHeight, static_cast<int>(stride)}; };

  const calib::CameraCalibration camera = lens();
  const depth::SphereSweep sweep(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse());
  depth::SphereSweepOptions one_at_a_time;
  one_at_a_time.simd = false;
  const depth::SphereSweep scalar(camera.camera, kWidth, kHeight, camera.camera, kWidth, kHeight, kT_l_r.inverse(), one_at_a_time);
  const depth::GreyImage l{left.data(), kWidth, kHeight, kWidth}, r{right.data(), kWidth, kHeight, kWidth};
  const depth::SweepResult want = scalar.estimate(l, r, {far.view, near.view});
  const depth::SweepResult got =
      sweep.estimate(at(0), at(1), {{at(3), far.view.T_earlier_reference}, {at(2), near.view.T_earlier_reference}});
  munmap(mapped, bytes);
  ASSERT_GT(want.tiles_decided_by_motion, 100);  // the views took part
  EXPECT_EQ(got.tiles_matched, want.tiles_matched);
  EXPECT_EQ(got.tiles_decided_by_motion, want.tiles_decided_by_motion);
  int differing = 0;
  for (int row = 0; row < want.inverse_depth.rows(); ++row)
    for (int col = 0; col < want.inverse_depth.cols(); ++col) differing += got.inverse_depth.at(row, col) != want.inverse_depth.at(row, col);
  EXPECT_EQ(differing, 0) << "tiles";
  EXPECT_EQ(got.confidence, want.confidence);
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

}  // namespace
}  // namespace telesphere::xr
