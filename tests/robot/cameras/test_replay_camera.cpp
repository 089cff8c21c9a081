// SPDX-License-Identifier: MIT
/// @brief ReplayCamera: frames on the fixed grid with the grid instant as capture time, frames a
///        slow consumer missed counted as lost (never queued), a shared start instant pairs two
///        cameras exactly, stop() ends waiting at once, bad set-ups refused. Time is simulated where
///        the test is about time (a slow consumer, timeouts, stop): no sleeps.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "robot/cameras/replay_camera.h"
#include "robot/clock/sim_clock.h"
#include "tests/eventually.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

std::vector<cameras::CameraFrame> frames(int count) {
  std::vector<cameras::CameraFrame> out;
  for (int i = 0; i < count; ++i) {
    cameras::CameraFrame f;
    f.width = 4;
    f.height = 2;
    f.stride_bytes = 12;
    f.pixels = std::make_shared<std::vector<std::uint8_t>>(24, static_cast<std::uint8_t>(i));
    out.push_back(f);
  }
  return out;
}

TEST(ReplayCamera, DeliversFramesOnTheGridCyclingTheInput) {
  clock::SteadyClock clock;
  cameras::ReplayCameraConfig config;
  config.fps = 200.0;
  cameras::ReplayCamera camera(clock, frames(3), config);
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
  clock::SimClock clock(1'000'000'000);
  cameras::ReplayCameraConfig config;
  config.fps = 1000.0;
  cameras::ReplayCamera camera(clock, frames(1), config);
  std::string error;
  ASSERT_TRUE(camera.start(&error));
  ASSERT_TRUE(camera.nextFrame(1000ms));  // frame 0, due at the start
  clock.advance(30'000'000);              // the consumer is busy for 30 ms: frames 1..30 come due
  const auto f = camera.nextFrame(1000ms);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->sequence, 30u);  // the newest, not a stale one
  EXPECT_EQ(f->capture_ns, 1'030'000'000);
  EXPECT_EQ(camera.stats().lost, 29u);
}

/// A simulated clock that moves 1 ms forward each time it is read: a camera waiting on it sees
/// time pass as fast as it looks, and how often it looked says that it is waiting.
class SteppingClock final : public clock::Clock {
 public:
  explicit SteppingClock(std::int64_t start_ns) : now_ns_(start_ns) {}
  std::int64_t nowNs() const override {
    ++reads_;
    return now_ns_.fetch_add(1'000'000);
  }
  std::int64_t peekNs() const { return now_ns_; }
  int reads() const { return reads_; }

 private:
  mutable std::atomic<std::int64_t> now_ns_;
  mutable std::atomic<int> reads_{0};
};

TEST(ReplayCamera, TwoCamerasWithOneStartInstantCarryEqualStamps) {
  clock::SteadyClock clock;
  cameras::ReplayCameraConfig config;
  config.fps = 100.0;
  config.start_ns = clock.nowNs();
  cameras::ReplayCamera left(clock, frames(2), config), right(clock, frames(2), config);
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
  SteppingClock clock(1'000'000'000);
  cameras::ReplayCameraConfig config;
  config.fps = 0.5;  // next frame only after 2 s
  cameras::ReplayCamera camera(clock, frames(1), config);
  std::string error;
  ASSERT_TRUE(camera.start(&error));
  ASSERT_TRUE(camera.nextFrame(100ms));  // frame 0 is due at once
  const std::int64_t before_timeout = clock.peekNs();
  EXPECT_FALSE(camera.nextFrame(20ms));  // frame 1 is not: nothing after the timeout, on the camera's clock
  EXPECT_GE(clock.peekNs() - before_timeout, 20'000'000);
  EXPECT_LE(clock.peekNs() - before_timeout, 25'000'000);
  // stop() from another thread once nextFrame waits (it keeps looking at the clock).
  const int reads_at_call = clock.reads();
  std::atomic<int> reads_at_stop{0};
  std::thread stopper([&] {
    EXPECT_TRUE(test::eventually([&] { return clock.reads() >= reads_at_call + 3; }));
    camera.stop();
    reads_at_stop = clock.reads();
  });
  EXPECT_FALSE(camera.nextFrame(10000ms));
  stopper.join();
  // Returned at its next look after the stop (a camera that ignored it would look ~2000 times,
  // until frame 1 is due).
  EXPECT_LE(clock.reads() - reads_at_stop, 2);
  EXPECT_FALSE(camera.nextFrame(10ms));
}

TEST(ReplayCamera, RefusesNoFramesAndBadRates) {
  clock::SteadyClock clock;
  std::string error;
  cameras::ReplayCamera none(clock, {}, {});
  EXPECT_FALSE(none.start(&error));
  EXPECT_NE(error.find("no frames"), std::string::npos);
  cameras::ReplayCameraConfig config;
  config.fps = 0.0;
  cameras::ReplayCamera zero(clock, frames(1), config);
  EXPECT_FALSE(zero.start(&error));
  EXPECT_NE(error.find("frame rate"), std::string::npos);
  std::vector<cameras::CameraFrame> short_frames = frames(1);
  short_frames[0].height = 100;
  cameras::ReplayCamera bad(clock, short_frames, {});
  EXPECT_FALSE(bad.start(&error));
}

}  // namespace
}  // namespace telesphere::robot
