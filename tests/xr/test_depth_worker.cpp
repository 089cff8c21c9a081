// SPDX-License-Identifier: MIT
/// @brief DepthWorker on decoded pairs of a rendered room with a box 0.5 m ahead, at a size that
///        the box filter does not divide (970 × 545, filtered by 2 with the last column and row
///        dropped): both cameras' radii find the box, the grids are published, a pair of the same
///        sequence is ignored; on the caller's thread (the replay) the estimate is there at once and
///        the same pairs give the same grids; a calibration without a stereo pair says why.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cerrno>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "app/bench/prerendered_frames.h"
#include "calib/camera_resolution.h"
#include "robot/cameras/synthetic_scene.h"
#include "tests/xr/scene_grey.h"
#include "tests/xr/stripes_room.h"
#include "xr/frame_loop/depth_worker.h"

namespace telesphere::xr {
namespace {

using namespace std::chrono_literals;

constexpr int kPairWidth = 970, kPairHeight = 545;

/// The simulated rig at its calibrated 4K (the worker scales it to the pairs' size).
calib::SystemCalibration rig() { return bench::simulatedRig(3840, 2160); }

/// The luma of the scene seen from T_world_cam through the rig's lens at kPairWidth × kPairHeight.
std::shared_ptr<const render::YuvPlanes> luma(const std::shared_ptr<robot::cameras::SyntheticScene>& scene,
                                               const Eigen::Isometry3d& T_world_cam) {
  std::string error;
  const auto lens = calib::atResolution(rig().cameras[0], kPairWidth, kPairHeight, &error);
  return test_scenes::lumaPlane(scene, lens->camera, kPairWidth, kPairHeight, T_world_cam);
}

/// The nice value of this process's thread named `name` (Linux: /proc/self/task), none if no thread has it.
std::optional<int> threadNice(const std::string& name) {
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string thread_name;
    if (!std::getline(comm, thread_name) || thread_name != name) continue;
    std::ifstream stat(task.path() / "stat");
    std::string line;
    std::getline(stat, line);
    // Fields 3 on follow the name's closing parenthesis; the nice value is field 19.
    std::istringstream fields(line.substr(line.rfind(')') + 2));
    std::string field;
    for (int i = 3; i <= 19; ++i) fields >> field;
    return std::stoi(field);
  }
  return std::nullopt;
}

TEST(DepthWorker, BothCamerasFindTheBoxAheadInDecodedPairsOfAnOddSize) {
  auto scene = std::make_shared<robot::cameras::SyntheticScene>();
  robot::cameras::SurfaceStyle style;
  Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
  T_world_room.translation() = Eigen::Vector3d(0.0, -0.2, 1.0);
  scene->addRoom("room", T_world_room, Eigen::Vector3d(2.5, 1.4, 2.0), style, style, style, style);
  Eigen::Isometry3d T_world_box = Eigen::Isometry3d::Identity();
  T_world_box.translation() = Eigen::Vector3d(0.032, 0.0, 0.6);  // straight ahead of the rig's middle
  scene->addBox("box", robot::cameras::fixedPose(T_world_box), Eigen::Vector3d(0.15, 0.15, 0.1), style);

  auto pair = std::make_shared<video::DecodedStereoFrame>();
  pair->frame.set_sequence(7);
  pair->frame.mutable_stamps()->set_capture_ns(1'000'000'000);
  pair->left = luma(scene, Eigen::Isometry3d::Identity());
  pair->right = luma(scene, *rig().T_cam_l_cam_r);

  frame_loop::DepthWorker worker(rig());
  EXPECT_FALSE(worker.newest());
  worker.offer(pair);
  worker.offer(pair);  // the same sequence again: ignored
  std::shared_ptr<const frame_loop::DepthEstimate> estimate;
  for (int i = 0; i < 300 && !(estimate = worker.newest()); ++i) std::this_thread::sleep_for(20ms);
  ASSERT_TRUE(estimate) << worker.stats().last_error;
  EXPECT_EQ(worker.stats().offered, 1u);
  EXPECT_EQ(estimate->frame_sequence, 7u);
  EXPECT_EQ(estimate->capture_ns, 1'000'000'000);
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE(i == 0 ? "left" : "right");
    EXPECT_NEAR(estimate->radius_m[i], 0.5, 0.05);  // the box's face fills the centre
    ASSERT_TRUE(estimate->grid[i]);
    EXPECT_GT(estimate->matched_fraction[i], 0.6);
    // Straight back (a 195° lens does not see it): filled, finite.
    EXPECT_TRUE(std::isfinite(estimate->grid[i]->sample({0, 0, -1})));
  }
  EXPECT_GT(estimate->sweep_ms, 0.0);
  // The sweep's thread yields the cores to the frame loop's where they share them: nice 10, or
  // the process's own where it already runs nicer (a thread may not lower its nice unprivileged).
  EXPECT_EQ(frame_loop::DepthWorkerOptions{}.thread_nice, 10);
  errno = 0;
  const int own_nice = getpriority(PRIO_PROCESS, 0);
  ASSERT_EQ(errno, 0);
  EXPECT_EQ(threadNice("ts-depth"), std::max(own_nice, frame_loop::DepthWorkerOptions{}.thread_nice));

  // On the caller's thread (the offline replay): the estimate is there when offer returns, and
  // two workers given the same pairs give the same grids to the bit.
  frame_loop::DepthWorkerOptions inline_options;
  inline_options.on_caller_thread = true;
  frame_loop::DepthWorker a(rig(), inline_options), b(rig(), inline_options);
  for (std::uint64_t sequence : {8u, 9u}) {
    auto next = std::make_shared<video::DecodedStereoFrame>(*pair);
    next->frame.set_sequence(sequence);
    next->frame.mutable_stamps()->set_capture_ns(std::int64_t(sequence) * 100'000'000);
    a.offer(next);
    ASSERT_TRUE(a.newest()) << a.stats().last_error;
    EXPECT_EQ(a.newest()->frame_sequence, sequence);
    b.offer(next);
  }
  EXPECT_EQ(a.stats().estimated, 2u);
  EXPECT_EQ(a.stats().skipped, 0u);
  for (int i = 0; i < 2; ++i) {
    const render::InverseDepthGrid &ga = *a.newest()->grid[i], &gb = *b.newest()->grid[i];
    ASSERT_EQ(ga.rows() * ga.cols(), gb.rows() * gb.cols());
    EXPECT_TRUE(std::equal(ga.data(), ga.data() + ga.rows() * ga.cols(), gb.data()));
    EXPECT_EQ(a.newest()->radius_m[i], b.newest()->radius_m[i]);
    EXPECT_NEAR(a.newest()->radius_m[i], estimate->radius_m[i], 0.01);
  }
}

/// A pair of `scene` seen by the rig at p_robot_rig (the left camera's centre, not turned), with
/// each camera's pose as the robot sends it (`source`).
std::shared_ptr<video::DecodedStereoFrame> pairAt(const std::shared_ptr<robot::cameras::SyntheticScene>& scene,
                                                  const Eigen::Vector3d& p_robot_rig, std::uint64_t sequence,
                                                  link::proto::PoseSource source = link::proto::POSE_SOURCE_JOINT_BUFFER) {
  return test_scenes::rigPairAt(scene, rig(), kPairWidth, kPairHeight, p_robot_rig, sequence, source);
}

/// The board's tiles (object 1) in a left camera's grid at the rig's origin, and the fraction of
/// them within 0.1 1/m of the truth toward their centres.
int onBoard(const robot::cameras::SyntheticScene& scene, const render::InverseDepthGrid& grid, double* right_fraction) {
  const robot::cameras::SceneView view = scene.view(0, Eigen::Isometry3d::Identity());
  int board = 0, right = 0;
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      robot::cameras::SceneHit hit;
      if (!view.intersect(grid.tileCentre(row, col), &hit) || hit.object != 1) continue;
      ++board;
      right += std::abs(grid.at(row, col) - 1.0 / hit.distance) < 0.1;
    }
  *right_fraction = board ? static_cast<double>(right) / board : 0.0;
  return board;
}

/// `pair` again, captured `seconds` later as the sequence after `sequence` (the arm still, the scene too).
std::shared_ptr<video::DecodedStereoFrame> again(const std::shared_ptr<video::DecodedStereoFrame>& pair, std::uint64_t sequence,
                                                 double seconds) {
  auto next = std::make_shared<video::DecodedStereoFrame>(*pair);
  next->frame.set_sequence(sequence);
  next->frame.mutable_stamps()->set_capture_ns(pair->frame.stamps().capture_ns() + static_cast<std::int64_t>(seconds * 1e9));
  return next;
}

/// The room and, 0.8 m ahead of the rig's middle, a board of vertical stripes 2 cm apart; the arm
/// brought the rig from 5 cm to the left (and 1 cm lower), through 1 cm, to the origin: three pairs
/// 100 ms apart.
struct StripesBroughtIn {
  std::shared_ptr<robot::cameras::SyntheticScene> scene;
  std::vector<std::shared_ptr<video::DecodedStereoFrame>> pairs;
};
StripesBroughtIn stripesBroughtIn() {
  auto scene = test_scenes::room(true);
  test_scenes::addStripesBoard(*scene, {0.032, 0.0, 0.8});
  std::vector<std::shared_ptr<video::DecodedStereoFrame>> pairs = {
      pairAt(scene, {-0.05, 0.01, 0.0}, 1), pairAt(scene, {-0.01, 0.01, 0.0}, 2), pairAt(scene, {0.0, 0.0, 0.0}, 3)};
  return {std::move(scene), std::move(pairs)};
}

TEST(DepthWorker, WhereTheArmHasMovedTheCamerasEarlierImagesDecideStripesThePairCannot) {
  const auto [scene, pairs] = stripesBroughtIn();

  frame_loop::DepthWorkerOptions options;
  options.on_caller_thread = true;
  frame_loop::DepthWorker moving(rig(), options);
  options.motion_views = 0;
  frame_loop::DepthWorker pair_alone(rig(), options);
  for (const auto& pair : pairs) {
    moving.offer(pair);
    pair_alone.offer(pair);
  }
  const auto with_views = moving.newest(), without = pair_alone.newest();
  ASSERT_TRUE(with_views && without) << moving.stats().last_error << pair_alone.stats().last_error;
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE(i == 0 ? "left" : "right");
    // Both earlier pairs are within reach: 5.1 cm the farthest, then the one nearest a quarter of it.
    EXPECT_EQ(with_views->motion_views[i], 2);
    EXPECT_NEAR(with_views->motion_baseline_m[i], std::hypot(0.05, 0.01), 1e-9);
    EXPECT_GT(with_views->tiles_decided_by_motion[i], 100);
    EXPECT_EQ(without->motion_views[i], 0);
    EXPECT_NEAR(with_views->radius_m[i], 0.8, 0.05);  // the board fills the centre
  }
  double with_right = 0, without_right = 0;
  ASSERT_GT(onBoard(*scene, *with_views->grid[0], &with_right), 150);
  onBoard(*scene, *without->grid[0], &without_right);
  std::printf("board tiles within 0.1 1/m: %.1f %% with the views, %.1f %% the pair alone; matched %.1f %% / %.1f %%\n",
              100 * with_right, 100 * without_right, 100 * with_views->matched_fraction[0], 100 * without->matched_fraction[0]);
  EXPECT_GT(with_right, 0.85);
  EXPECT_LT(without_right, with_right - 0.2);

  // A new calibration (other T_robot_cam for the same joints) or a time that went back (a replay
  // restarted) leaves the history behind: no views.
  auto recalibrated = std::make_shared<video::DecodedStereoFrame>(*pairs[2]);
  recalibrated->frame.set_sequence(4);
  recalibrated->frame.mutable_stamps()->set_capture_ns(pairs[2]->frame.stamps().capture_ns() + 100'000'000);
  recalibrated->frame.set_calibration_generation(2);
  moving.offer(recalibrated);
  ASSERT_EQ(moving.newest()->frame_sequence, 4u);
  EXPECT_EQ(moving.newest()->motion_views[0], 0);
  EXPECT_EQ(moving.newest()->motion_views[1], 0);
  auto back_in_time = std::make_shared<video::DecodedStereoFrame>(*pairs[0]);
  back_in_time->frame.set_sequence(5);
  back_in_time->frame.set_calibration_generation(2);
  moving.offer(back_in_time);  // captured before the pair above, 5 cm away from it
  ASSERT_EQ(moving.newest()->frame_sequence, 5u);
  EXPECT_EQ(moving.newest()->motion_views[0], 0);

  // The farthest earlier pair lies 8 cm straight behind (a motion along the optical axis: the
  // view's middle has no parallax), one 3 cm to the left: only the one across the axis is taken.
  frame_loop::DepthWorker along_axis(rig(), [] {
    frame_loop::DepthWorkerOptions o;
    o.on_caller_thread = true;
    return o;
  }());
  along_axis.offer(pairAt(scene, {0.0, 0.0, -0.08}, 1));
  along_axis.offer(pairAt(scene, {-0.03, 0.0, 0.0}, 2));
  along_axis.offer(pairs[2]);
  ASSERT_TRUE(along_axis.newest());
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(along_axis.newest()->motion_views[i], 1);
    EXPECT_NEAR(along_axis.newest()->motion_baseline_m[i], 0.03, 1e-9);
  }

  // Poses from the calibration alone (no joint states) say nothing of the motion: no views.
  frame_loop::DepthWorker fixed(rig(), [] {
    frame_loop::DepthWorkerOptions o;
    o.on_caller_thread = true;
    return o;
  }());
  for (std::uint64_t sequence = 1; sequence <= 3; ++sequence) {
    auto pair = std::make_shared<video::DecodedStereoFrame>(*pairs[sequence - 1]);
    for (auto* image : {pair->frame.mutable_left(), pair->frame.mutable_right()})
      image->set_pose_source(link::proto::POSE_SOURCE_FIXED_CALIBRATION);
    fixed.offer(pair);
  }
  ASSERT_TRUE(fixed.newest());
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(fixed.newest()->motion_views[i], 0);
    EXPECT_EQ(fixed.newest()->tiles_decided_by_motion[i], 0);
  }
}

TEST(DepthWorker, WithTheArmStillTheLastImagesFromElsewhereKeepDecidingTheStripes) {
  // The arm brings the rig in as above, then holds it still for 3 s (pairs of the same view): the
  // recent history (2 s) then holds only images from here, without a baseline. The last images
  // from elsewhere are kept (one a place, for motion_keep_s) and still decide the board.
  const auto [scene, pairs] = stripesBroughtIn();
  frame_loop::DepthWorkerOptions options;
  options.on_caller_thread = true;
  frame_loop::DepthWorker worker(rig(), options);
  for (const auto& pair : pairs) worker.offer(pair);
  std::uint64_t sequence = 3;
  for (const double still_s : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0}) {
    worker.offer(again(pairs[2], ++sequence, still_s));
    ASSERT_TRUE(worker.newest());
    ASSERT_EQ(worker.newest()->frame_sequence, sequence);
    // Every sweep has its views, also the one at which the images from elsewhere leave the 2 s
    // history (2.0 s still: they were captured 2.1 and 2.2 s before it).
    EXPECT_EQ(worker.newest()->motion_views[0], 2) << still_s << " s still";
  }
  auto estimate = worker.newest();
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE(i == 0 ? "left" : "right");
    EXPECT_EQ(estimate->motion_views[i], 2);
    EXPECT_NEAR(estimate->motion_baseline_m[i], std::hypot(0.05, 0.01), 1e-9);
    EXPECT_GT(estimate->tiles_decided_by_motion[i], 100);
  }
  double right = 0;
  ASSERT_GT(onBoard(*scene, *estimate->grid[0], &right), 150);
  std::printf("board tiles within 0.1 1/m after 3 s still: %.1f %%\n", 100 * right);
  EXPECT_GT(right, 0.85);

  // The kept images age out too: still for longer than motion_keep_s, the pair alone.
  worker.offer(again(pairs[2], ++sequence, options.motion_keep_s + 0.5));
  estimate = worker.newest();
  ASSERT_EQ(estimate->frame_sequence, sequence);
  EXPECT_EQ(estimate->motion_views[0], 0);
  EXPECT_EQ(estimate->motion_views[1], 0);
}

TEST(DepthWorker, ACalibrationWithoutAStereoPairSaysWhy) {
  calib::SystemCalibration mono = rig();
  mono.cameras.pop_back();
  mono.T_cam_l_cam_r.reset();
  frame_loop::DepthWorker worker(mono);
  auto pair = std::make_shared<video::DecodedStereoFrame>();
  auto planes = std::make_shared<render::YuvPlanes>();
  planes->width = 64;
  planes->height = 48;
  planes->y.assign(64 * 48, 100);
  pair->left = pair->right = planes;
  worker.offer(pair);
  for (int i = 0; i < 200 && worker.stats().last_error.empty(); ++i) std::this_thread::sleep_for(10ms);
  EXPECT_NE(worker.stats().last_error.find("no stereo pair"), std::string::npos) << worker.stats().last_error;
  EXPECT_FALSE(worker.newest());
}

}  // namespace
}  // namespace telesphere::xr
