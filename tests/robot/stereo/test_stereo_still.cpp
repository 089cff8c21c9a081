// SPDX-License-Identifier: MIT
/// @brief Calibration stills (robot/stereo/stereo_still.h): the first pair captured after the request,
///        full resolution, grey (Mono8 rows unpadded, RGB to luma, Bayer demosaiced), the head
///        joints interpolated at the capture time only when joint states bracket it — waiting
///        for the state after, refusing stale pairs, missing and lost joint states with reasons.
///        Other threads act on events, never after a sleep: a pair is offered once take() waits
///        for one, a joint state pushed once take() waits for it (takersWaiting, waitingReaders).
#include <gtest/gtest.h>

#include <memory>
#include <thread>

#include "robot/head/head_geometry.h"
#include "robot/link/link_pose.h"
#include "robot/clock/sim_clock.h"
#include "robot/stereo/stereo_still.h"
#include "tests/eventually.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

cameras::CameraFrame frame(cameras::PixelFormat format, int w, int h, int stride, std::int64_t capture_ns,
                  const std::function<std::uint8_t(int x, int y, int c)>& value) {
  cameras::CameraFrame f;
  f.format = format;
  f.width = w;
  f.height = h;
  f.stride_bytes = stride;
  f.capture_ns = capture_ns;
  const int bpp = cameras::bytesPerPixel(format);
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(std::size_t(stride) * std::size_t(h), 0xEE);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < bpp; ++c) (*pixels)[std::size_t(y * stride + x * bpp + c)] = value(x, y, c);
  f.pixels = pixels;
  return f;
}

arm::JointState state(std::int64_t t_ns, double q0) {
  arm::JointState s;
  s.t_ns = t_ns;
  s.q << q0, -0.3, 0.4, 0.1, 0.6, -0.2;
  return s;
}

using test::eventually;

/// Offers `pair` from another thread once take() waits for one (as the video path would).
std::thread offerOnceWaiting(stereo::StereoStillTaker& taker, stereo::StereoFrame pair, std::uint64_t sequence) {
  return std::thread([&taker, pair, sequence] {
    EXPECT_TRUE(eventually([&] { return taker.takersWaiting() > 0; }));
    taker.offer(pair, sequence);
  });
}

/// Pushes `state` from another thread once a reader waits for a sample (as the arm's reports would).
std::thread pushOnceWaited(head::JointStateBuffer& buffer, arm::JointState state) {
  return std::thread([&buffer, state] {
    EXPECT_TRUE(eventually([&] { return buffer.waitingReaders() > 0; }));
    buffer.push(state);
  });
}

struct StillRig {
  clock::SimClock clock{1'000'000'000};
  head::JointStateBuffer joints{head::HeadGeometry::example()};
  stereo::StereoStillTaker taker{joints, clock};
  std::thread offerSoon(stereo::StereoFrame pair, std::uint64_t sequence) { return offerOnceWaiting(taker, pair, sequence); }
};

TEST(StereoStill, ThePairAfterTheRequestAtFullResolutionWithBracketedJoints) {
  StillRig rig;
  const std::int64_t t0 = rig.clock.nowNs();
  // A pair captured before the request is there already: it must not be the still.
  stereo::StereoFrame old;
  old.left = frame(cameras::PixelFormat::kMono8, 8, 4, 8, t0 - 5'000'000, [](int, int, int) { return 1; });
  old.right = old.left;
  rig.taker.offer(old, 1);
  ASSERT_TRUE(rig.joints.push(state(t0, 0.10)));
  ASSERT_TRUE(rig.joints.push(state(t0 + 10'000'000, 0.20)));
  ASSERT_TRUE(rig.joints.push(state(t0 + 20'000'000, 0.30)));
  stereo::StereoFrame pair;  // Mono8 with row padding, RGB on the right
  pair.left = frame(cameras::PixelFormat::kMono8, 5, 3, 8, t0 + 4'000'000, [](int x, int y, int) { return 10 * y + x; });
  pair.right = frame(cameras::PixelFormat::kRgb8, 5, 3, 16, t0 + 4'500'000, [](int x, int, int c) {
    return c == 0 ? 200 : c == 1 ? 100 : 50 + x;
  });
  auto offering = rig.offerSoon(pair, 7);
  link::proto::CalibrationStill still;
  std::string error;
  ASSERT_TRUE(rig.taker.take(&still, 2000ms, &error)) << error;
  offering.join();
  EXPECT_EQ(still.sequence(), 7u);
  EXPECT_EQ(still.capture_ns(), t0 + 4'000'000);
  EXPECT_EQ(still.left().width(), 5u);
  EXPECT_EQ(still.left().height(), 3u);
  ASSERT_EQ(still.left().gray8().size(), 15u);  // rows without the padding
  EXPECT_EQ(std::uint8_t(still.left().gray8()[2 * 5 + 3]), 23);
  ASSERT_EQ(still.right().gray8().size(), 15u);
  for (int x = 0; x < 5; ++x)  // Rec. 601 luma, rounded
    EXPECT_EQ(std::uint8_t(still.right().gray8()[std::size_t(x)]), (299 * 200 + 587 * 100 + 114 * (50 + x) + 500) / 1000);
  ASSERT_EQ(still.head_joints_size(), 6);
  EXPECT_NEAR(still.head_joints(0), 0.14, 1e-12);  // 0.4 of the way from 0.10 to 0.20
  EXPECT_EQ(still.joints_before_ns(), t0);
  EXPECT_EQ(still.joints_after_ns(), t0 + 10'000'000);
  const Eigen::Isometry3d T = link::fromLinkPose(still.right().t_robot_cam());
  EXPECT_TRUE(T.isApprox(*rig.joints.T_robot_cam(cameras::CameraSide::kRight, t0 + 4'500'000), 1e-12));
  EXPECT_EQ(rig.taker.taken(), 1u);
}

TEST(StereoStill, WaitsForTheJointStateAfterTheCaptureButNeverExtrapolates) {
  StillRig rig;
  const std::int64_t t0 = rig.clock.nowNs();
  ASSERT_TRUE(rig.joints.push(state(t0, 0.1)));
  stereo::StereoFrame pair;
  pair.left = frame(cameras::PixelFormat::kMono8, 4, 4, 4, t0 + 6'000'000, [](int, int, int) { return 9; });
  pair.right = pair.left;
  // The buffer would extrapolate 6 ms; the still waits for the state after, which comes later.
  auto offering = rig.offerSoon(pair, 3);
  std::thread arm = pushOnceWaited(rig.joints, state(t0 + 10'000'000, 0.2));
  link::proto::CalibrationStill still;
  std::string error;
  ASSERT_TRUE(rig.taker.take(&still, 2000ms, &error)) << error;
  offering.join();
  arm.join();
  EXPECT_EQ(still.joints_after_ns(), t0 + 10'000'000);
  EXPECT_NEAR(still.head_joints(0), 0.16, 1e-12);
  // No state after it ever: refused with the reason, after the timeout.
  rig.clock.set(t0 + 12'000'000);  // the request comes after the first pair: that one is stale now
  stereo::StereoFrame later = pair;
  later.left.capture_ns = later.right.capture_ns = t0 + 15'000'000;
  auto offering2 = rig.offerSoon(later, 4);
  EXPECT_FALSE(rig.taker.take(&still, 200ms, &error));
  offering2.join();
  EXPECT_NE(error.find("after the capture time arrived in time"), std::string::npos) << error;
}

TEST(StereoStill, RefusesWithoutAFreshPairOrAnyJointState) {
  StillRig rig;
  std::string error;
  link::proto::CalibrationStill still;
  EXPECT_FALSE(rig.taker.take(&still, 50ms, &error));  // nothing offered
  EXPECT_NE(error.find("no stereo frame captured within 50 ms"), std::string::npos) << error;
  stereo::StereoFrame pair;
  pair.left = frame(cameras::PixelFormat::kMono8, 4, 4, 4, rig.clock.nowNs() + 1, [](int, int, int) { return 9; });
  pair.right = pair.left;
  auto offering = rig.offerSoon(pair, 1);
  EXPECT_FALSE(rig.taker.take(&still, 150ms, &error));
  offering.join();
  EXPECT_NE(error.find("no joint states at all"), std::string::npos) << error;
  EXPECT_EQ(rig.taker.taken(), 0u);
}

// With a manipulator (hand-eye calibration) its joints are bracketed and interpolated at the
// capture time too, with their forward kinematics; a manipulator that stopped reporting makes
// the still fail with the reason, not carry stale joints.
TEST(StereoStill, TheManipulatorsJointsAreBracketedToo) {
  clock::SimClock clock{1'000'000'000};
  head::JointStateBuffer joints{head::HeadGeometry::example()};
  head::JointStateBuffer manipulator{head::HeadGeometry{}};
  stereo::StereoStillTaker taker{joints, clock, &manipulator};
  const std::int64_t t0 = clock.nowNs();
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(joints.push(state(t0 + i * 10'000'000, 0.1 * (i + 1))));
  ASSERT_TRUE(manipulator.push(state(t0 - 2'000'000, 0.5)));
  stereo::StereoFrame pair;
  pair.left = frame(cameras::PixelFormat::kMono8, 4, 4, 4, t0 + 4'000'000, [](int, int, int) { return 9; });
  pair.right = pair.left;
  std::thread offering = offerOnceWaiting(taker, pair, 5);
  std::thread report = pushOnceWaited(manipulator, state(t0 + 8'000'000, 0.6));  // the next report comes later
  link::proto::CalibrationStill still;
  std::string error;
  ASSERT_TRUE(taker.take(&still, 2000ms, &error)) << error;
  offering.join();
  report.join();
  ASSERT_EQ(still.manipulator_joints_size(), 6);
  EXPECT_NEAR(still.manipulator_joints(0), 0.5 + 0.1 * 6.0 / 10.0, 1e-12);
  EXPECT_EQ(still.manipulator_before_ns(), t0 - 2'000'000);
  EXPECT_EQ(still.manipulator_after_ns(), t0 + 8'000'000);
  EXPECT_TRUE(link::fromLinkPose(still.t_mount_wrist()).isApprox(*manipulator.T_robot_flange(t0 + 4'000'000), 1e-12));
  EXPECT_TRUE(link::fromLinkPose(still.t_robot_flange()).isApprox(*joints.T_robot_flange(t0 + 4'000'000), 1e-12));

  // The manipulator stops reporting: the next still is refused, naming it.
  clock.set(t0 + 12'000'000);
  stereo::StereoFrame later = pair;
  later.left.capture_ns = later.right.capture_ns = t0 + 15'000'000;
  ASSERT_TRUE(joints.push(state(t0 + 30'000'000, 0.4)));
  std::thread offering_later = offerOnceWaiting(taker, later, 6);
  EXPECT_FALSE(taker.take(&still, 200ms, &error));
  offering_later.join();
  EXPECT_NE(error.find("no joint state of the manipulator after the capture time"), std::string::npos) << error;
}

TEST(StereoStill, BayerIsDemosaicedToLumaAndBrokenFramesAreRefused) {
  // A uniform colour through an RG mosaic comes back as its luma everywhere.
  const cameras::CameraFrame bayer = frame(cameras::PixelFormat::kBayerRG8, 6, 4, 6, 0, [](int x, int y, int) {
    return (y % 2 == 0) ? (x % 2 == 0 ? 200 : 100) : (x % 2 == 0 ? 100 : 40);
  });
  std::string gray, error;
  ASSERT_TRUE(stereo::toGray8(bayer, &gray, &error)) << error;
  ASSERT_EQ(gray.size(), 24u);
  for (char v : gray) EXPECT_EQ(std::uint8_t(v), (299 * 200 + 587 * 100 + 114 * 40 + 500) / 1000);
  cameras::CameraFrame broken = bayer;
  broken.stride_bytes = 3;  // shorter than a row
  EXPECT_FALSE(stereo::toGray8(broken, &gray, &error));
  broken = bayer;
  broken.pixels.reset();
  EXPECT_FALSE(stereo::toGray8(broken, &gray, &error));
  EXPECT_EQ(error, "camera frame without valid pixels");
}

}  // namespace
}  // namespace telesphere::robot
