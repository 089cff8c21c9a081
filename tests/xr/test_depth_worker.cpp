// SPDX-License-Identifier: MIT
/// @brief DepthWorker on decoded pairs of a rendered room with a box 0.5 m ahead, at a size that
///        the box filter does not divide (970 × 545, filtered by 2 with the last column and row
///        dropped): both cameras' radii find the box, the grids are published, a pair of the same
///        sequence is ignored; on the caller's thread (the replay) the estimate is there at once and
///        the same pairs give the same grids; a calibration without a stereo pair says why.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "app/bench/prerendered_frames.h"
#include "calib/camera_resolution.h"
#include "robot/clock/clock.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/stereo/stereo_still.h"
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
  robot::clock::SteadyClock clock;
  robot::cameras::SyntheticCameraOptions options;
  options.supersampling = 2;
  const robot::cameras::SyntheticCamera camera(lens->camera, kPairWidth, kPairHeight, scene, robot::cameras::fixedPose(T_world_cam),
                                               clock, options);
  std::string grey;
  EXPECT_TRUE(robot::stereo::toGray8(camera.renderAt(0), &grey, &error)) << error;
  auto planes = std::make_shared<render::YuvPlanes>();
  planes->width = kPairWidth;
  planes->height = kPairHeight;
  planes->y.assign(grey.begin(), grey.end());
  return planes;
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
