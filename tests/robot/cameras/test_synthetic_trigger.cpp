// SPDX-License-Identifier: MIT
/// @brief The synthetic cameras' shared trigger: its choice of tick, and two threaded cameras on a
///        simulated clock, one held up mid-frame while the clock moves on, which without the
///        trigger expose different ticks (no stereo pair) and with it the same.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>

#include "robot/clock/sim_clock.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/cameras/synthetic_trigger.h"

namespace telesphere::robot {
namespace {

TEST(SyntheticTrigger, TheFirstCameraClaimsAndALaggingPartnerFollows) {
  cameras::SyntheticTrigger trigger;
  EXPECT_EQ(trigger.tickFor(1, 1), 1);  // nothing claimed yet: its own
  EXPECT_EQ(trigger.tickFor(1, 1), 1);  // the partner at the same tick
  EXPECT_EQ(trigger.tickFor(2, 2), 2);  // on time: the next tick
  // The partner, done with tick 1 while the clock is at tick 4, renders tick 2 (claimed, not yet
  // rendered by it) rather than the latest.
  EXPECT_EQ(trigger.tickFor(2, 4), 2);
  EXPECT_EQ(trigger.followed(), 1u);
  // The first camera, behind now as well, claims the latest tick; the partner follows it there.
  EXPECT_EQ(trigger.tickFor(3, 5), 5);
  EXPECT_EQ(trigger.tickFor(3, 5), 5);  // claimed == wanted: nothing to follow
  EXPECT_EQ(trigger.followed(), 1u);
}

TEST(SyntheticTrigger, AClaimTheCameraHasRenderedOrStartedAfterIsNotFollowed) {
  cameras::SyntheticTrigger trigger;
  EXPECT_EQ(trigger.tickFor(10, 12), 12);
  // A camera past the claim (its next tick is 13) takes its own choice and claims it.
  EXPECT_EQ(trigger.tickFor(13, 15), 15);
  // A camera (re)started at tick 40 does not go back to a partner's old claim.
  EXPECT_EQ(trigger.tickFor(40, 40), 40);
  // An older wish never lowers the claim: a partner behind follows 40.
  EXPECT_EQ(trigger.tickFor(16, 41), 40);
  EXPECT_EQ(trigger.tickFor(41, 41), 41);
  EXPECT_EQ(trigger.followed(), 1u);
}

/// Holds a camera's render thread at a chosen tick (in its pose callback) until released.
class RenderGate {
 public:
  void holdAt(int side, std::int64_t tick_ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    hold_ns_[side] = tick_ns;
  }
  void pass(int side, std::int64_t t_ns) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (hold_ns_[side] != t_ns) return;
    held_[side] = true;
    changed_.notify_all();
    changed_.wait(lock, [&] { return hold_ns_[side] != t_ns; });
    held_[side] = false;
  }
  bool waitHeld(int side) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(30), [&] { return held_[side]; });
  }
  void release(int side) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      hold_ns_[side].reset();
    }
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::array<std::optional<std::int64_t>, 2> hold_ns_;
  std::array<bool, 2> held_{false, false};
};

Eigen::Isometry3d headPose(std::int64_t /*t_ns*/) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = cameras::DefaultSceneLayout{}.head_position;
  return T;
}

/// Ticks exposed by two cameras at 10 Hz: both expose tick 1, but the right camera is held in
/// it until the clock stands at tick 3.5, while the left one took tick 2 at 2.5 and is held
/// there. The right camera's next two frames after tick 1, as ticks (-1: none).
std::array<std::int64_t, 2> rightTicksAfterALag(bool shared_trigger, std::uint64_t* followed) {
  constexpr std::int64_t kP = 100'000'000;  // 10 Hz
  clock::SimClock clock(1);                         // the first tick is tick 1
  auto scene = std::make_shared<cameras::SyntheticScene>(cameras::defaultScene());
  Eigen::VectorXd p(6);
  p << 19.7, 19.7, 39.5, 31.5, -0.18, 0.59;
  const auto lens = *calib::GenericCamera::create("ds", p);
  RenderGate gate;
  gate.holdAt(0, 2 * kP);
  gate.holdAt(1, 1 * kP);
  cameras::SyntheticCameraOptions options;
  options.fps = 10.0;
  options.exposure_us = 0;  // delivered at the tick
  options.threads = 1;
  if (shared_trigger) options.trigger = std::make_shared<cameras::SyntheticTrigger>();
  options.name = "left";
  cameras::SyntheticCamera left(lens, 80, 64, scene, [&gate](std::int64_t t) { gate.pass(0, t); return headPose(t); }, clock,
                       options);
  options.name = "right";
  cameras::SyntheticCamera right(lens, 80, 64, scene, [&gate](std::int64_t t) { gate.pass(1, t); return headPose(t); },
                        clock, options);
  std::array<std::int64_t, 2> ticks{-1, -1};
  const auto tickOf = [&](cameras::SyntheticCamera& cam) -> std::int64_t {
    const auto frame = cam.nextFrame(std::chrono::seconds(30));
    return frame ? frame->capture_ns / kP : -1;
  };
  EXPECT_TRUE(left.start(nullptr) && right.start(nullptr));
  clock.set(kP);
  EXPECT_TRUE(gate.waitHeld(1));
  EXPECT_EQ(tickOf(left), 1);
  clock.set(2 * kP + kP / 2);
  EXPECT_TRUE(gate.waitHeld(0));  // the left camera renders tick 2
  clock.set(3 * kP + kP / 2);
  gate.release(1);
  EXPECT_EQ(tickOf(right), 1);
  ticks[0] = tickOf(right);
  gate.release(0);
  EXPECT_EQ(tickOf(left), 2);
  EXPECT_EQ(tickOf(left), 3);
  if (ticks[0] == 2) ticks[1] = tickOf(right);  // otherwise it has shown tick 3 already
  if (followed != nullptr && options.trigger) *followed = options.trigger->followed();
  left.stop();
  right.stop();
  return ticks;
}

TEST(SyntheticTrigger, ALaggingCameraExposesItsPartnersTickNotTheLatest) {
  // Without the trigger the right camera skips to the latest tick (3) while the left one
  // exposes 2: tick 2 has no pair (the failure seen in CI, there for seconds on end).
  const auto alone = rightTicksAfterALag(false, nullptr);
  EXPECT_EQ(alone[0], 3);
  // With it the right camera exposes tick 2 as well, then both tick 3.
  std::uint64_t followed = 0;
  const auto shared = rightTicksAfterALag(true, &followed);
  EXPECT_EQ(shared[0], 2);
  EXPECT_EQ(shared[1], 3);
  EXPECT_EQ(followed, 1u);
}

}  // namespace
}  // namespace telesphere::robot
