// SPDX-License-Identifier: MIT
/// @brief ReplayCamera: frames on the fixed grid with the grid instant as capture time, frames a
///        slow consumer missed counted as lost (never queued), a shared start instant pairs two
///        cameras exactly, stop() ends waiting at once, bad set-ups refused.
#include <gtest/gtest.h>

#include <thread>

#include "robot/replay_camera.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

std::vector<CameraFrame> frames(int count) {
  std::vector<CameraFrame> out;
  for (int i = 0; i < count; ++i) {
    CameraFrame f;
    f.width = 4;
    f.height = 2;
    f.stride_bytes = 12;
    f.pixels = std::make_shared<std::vector<std::uint8_t>>(24, static_cast<std::uint8_t>(i));
    out.push_back(f);
  }
  return out;
}

TEST(ReplayCamera, DeliversFramesOnTheGridCyclingTheInput) {
  SteadyClock clock;
  ReplayCameraConfig config;
  config.fps = 200.0;
  ReplayCamera camera(clock, frames(3), config);
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  std::int64_t first_ns = 0;
  for (int k = 0; k < 6; ++k) {
    const auto f = camera.nextFrame(1000ms);
    ASSERT_TRUE(f);
    if (k == 0) first_ns = f->capture_ns;
    // Consecutive unless the machine stalled (then the gap is counted as lost).
    const auto index = static_cast<std::int64_t>(f->sequence);
    EXPECT_EQ(f->capture_ns, first_ns + index * 5'000'000);
    EXPECT_EQ((*f->pixels)[0], static_cast<std::uint8_t>(index % 3));
    EXPECT_LE(f->capture_ns, clock.nowNs());  // never handed out before it is due
  }
  EXPECT_EQ(camera.stats().frames, 6u);
}

TEST(ReplayCamera, ASlowConsumerGetsTheNewestFrameAndTheRestCountAsLost) {
  SteadyClock clock;
  ReplayCameraConfig config;
  config.fps = 1000.0;
  ReplayCamera camera(clock, frames(1), config);
  std::string error;
  ASSERT_TRUE(camera.start(&error));
  ASSERT_TRUE(camera.nextFrame(1000ms));
  std::this_thread::sleep_for(30ms);  // ~30 frames come due meanwhile
  const std::int64_t now_ns = clock.nowNs();
  const auto f = camera.nextFrame(1000ms);
  ASSERT_TRUE(f);
  EXPECT_GE(f->sequence, 25u);
  EXPECT_GT(f->capture_ns, now_ns - 2'000'000);  // the newest, not a stale one
  EXPECT_EQ(camera.stats().lost, f->sequence - 1);
}

TEST(ReplayCamera, TwoCamerasWithOneStartInstantCarryEqualStamps) {
  SteadyClock clock;
  ReplayCameraConfig config;
  config.fps = 100.0;
  config.start_ns = clock.nowNs();
  ReplayCamera left(clock, frames(2), config), right(clock, frames(2), config);
  std::string error;
  ASSERT_TRUE(left.start(&error) && right.start(&error));
  for (int k = 0; k < 3; ++k) {
    const auto l = left.nextFrame(1000ms), r = right.nextFrame(1000ms);
    ASSERT_TRUE(l && r);
    // Same grid: equal sequence numbers carry equal stamps (a stall may skip one side ahead).
    const auto dk = static_cast<std::int64_t>(l->sequence) - static_cast<std::int64_t>(r->sequence);
    EXPECT_EQ(l->capture_ns - r->capture_ns, dk * 10'000'000);
  }
}

TEST(ReplayCamera, StopEndsWaitingAndTimeoutsReturnNothing) {
  SteadyClock clock;
  ReplayCameraConfig config;
  config.fps = 0.5;  // next frame only after 2 s
  ReplayCamera camera(clock, frames(1), config);
  std::string error;
  ASSERT_TRUE(camera.start(&error));
  ASSERT_TRUE(camera.nextFrame(100ms));     // frame 0 is due at once
  EXPECT_FALSE(camera.nextFrame(20ms));     // frame 1 is not
  std::thread stopper([&] {
    std::this_thread::sleep_for(20ms);
    camera.stop();
  });
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(camera.nextFrame(10000ms));
  stopper.join();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1500ms);  // returned on stop, not at the due time
  EXPECT_FALSE(camera.nextFrame(10ms));
}

TEST(ReplayCamera, RefusesNoFramesAndBadRates) {
  SteadyClock clock;
  std::string error;
  ReplayCamera none(clock, {}, {});
  EXPECT_FALSE(none.start(&error));
  EXPECT_NE(error.find("no frames"), std::string::npos);
  ReplayCameraConfig config;
  config.fps = 0.0;
  ReplayCamera zero(clock, frames(1), config);
  EXPECT_FALSE(zero.start(&error));
  EXPECT_NE(error.find("frame rate"), std::string::npos);
  std::vector<CameraFrame> short_frames = frames(1);
  short_frames[0].height = 100;
  ReplayCamera bad(clock, short_frames, {});
  EXPECT_FALSE(bad.start(&error));
}

}  // namespace
}  // namespace telesphere::robot
