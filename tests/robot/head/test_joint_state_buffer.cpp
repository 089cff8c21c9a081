// SPDX-License-Identifier: MIT
/// @brief JointStateBuffer: interpolation, camera poses by forward kinematics, refusal outside the
///        window, bounded extrapolation, gaps, ordering, capacity, and one writer with concurrent
///        readers; TrueCameraPoses, the simulation's truth read from such a buffer.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "robot/head/joint_state_buffer.h"
#include "robot/clock/sim_clock.h"
#include "robot/stereo/true_camera_poses.h"
#include "tests/eventually.h"

namespace telesphere::robot {
namespace {

constexpr std::int64_t kMs = 1'000'000;

/// Joints linear in time, so linear interpolation reproduces them exactly.
arm::JointVector linearJoints(std::int64_t t_ns) {
  const double t = static_cast<double>(t_ns) * 1e-9;
  arm::JointVector q;
  q << 0.1 + 0.5 * t, -0.3 + 0.2 * t, -1.0 - 0.1 * t, 0.2 * t, 0.8 - 0.3 * t, -0.4 + t;
  return q;
}

arm::JointState stateAt(std::int64_t t_ns) { return arm::JointState{t_ns, linearJoints(t_ns), arm::ArmStatus::kOk}; }

TEST(JointStateBuffer, InterpolatesJointsAndFollowsKinematicsForPoses) {
  const head::HeadGeometry geometry = head::HeadGeometry::example();
  head::JointStateBuffer buffer(geometry);
  for (int k = 0; k < 50; ++k) ASSERT_TRUE(buffer.push(stateAt(k * 10 * kMs)));
  const arm::Xarm6Kinematics kin;
  for (const std::int64_t t : {std::int64_t{0}, 5 * kMs, 123 * kMs, 250 * kMs + 1, 490 * kMs}) {
    const auto q = buffer.jointsAt(t);
    ASSERT_TRUE(q) << t;
    EXPECT_TRUE(q->isApprox(linearJoints(t), 1e-12));
    const auto T_l = buffer.T_robot_cam(cameras::CameraSide::kLeft, t);
    const auto T_r = buffer.T_robot_cam(cameras::CameraSide::kRight, t);
    ASSERT_TRUE(T_l && T_r);
    const Eigen::Isometry3d T_flange = kin.forward(*q);
    EXPECT_TRUE(T_l->isApprox(T_flange * geometry.T_flange_cam_l, 1e-12));
    EXPECT_TRUE(T_r->isApprox(T_flange * geometry.T_flange_cam_l * geometry.T_cam_l_cam_r, 1e-12));
    EXPECT_NEAR((T_l->translation() - T_r->translation()).norm(), 0.065, 1e-12);
  }
  // Between two samples, interpolation is linear in the joints (not in the pose).
  head::JointStateBuffer step(geometry);
  arm::JointVector a = arm::JointVector::Zero(), b = arm::JointVector::Zero();
  b[0] = 0.2;
  step.push({0, a, arm::ArmStatus::kOk});
  step.push({10 * kMs, b, arm::ArmStatus::kOk});
  EXPECT_NEAR((*step.jointsAt(2500'000))[0], 0.05, 1e-15);
}

TEST(JointStateBuffer, RefusesOutsideItsWindowAndExtrapolatesWithinTheBound) {
  head::JointStateBufferConfig config;
  config.max_extrapolation_ns = 20 * kMs;
  head::JointStateBuffer buffer(head::HeadGeometry::example(), config);
  EXPECT_FALSE(buffer.jointsAt(0));
  EXPECT_FALSE(buffer.window());
  buffer.push(stateAt(100 * kMs));
  EXPECT_TRUE(buffer.jointsAt(110 * kMs)->isApprox(linearJoints(100 * kMs)));  // one sample: held
  buffer.push(stateAt(110 * kMs));
  EXPECT_FALSE(buffer.jointsAt(99 * kMs));
  const auto extrapolated = buffer.jointsAt(125 * kMs);
  ASSERT_TRUE(extrapolated);
  EXPECT_TRUE(extrapolated->isApprox(linearJoints(125 * kMs), 1e-12));
  EXPECT_TRUE(buffer.jointsAt(130 * kMs));
  EXPECT_FALSE(buffer.jointsAt(130 * kMs + 1));
  EXPECT_FALSE(buffer.T_robot_cam(cameras::CameraSide::kLeft, 131 * kMs));
}

TEST(JointStateBuffer, RejectsDisorderedAndNonFiniteStatesAndRefusesAcrossGaps) {
  head::JointStateBufferConfig config;
  config.max_gap_ns = 50 * kMs;
  head::JointStateBuffer buffer(head::HeadGeometry::example(), config);
  EXPECT_TRUE(buffer.push(stateAt(10 * kMs)));
  EXPECT_FALSE(buffer.push(stateAt(10 * kMs)));
  EXPECT_FALSE(buffer.push(stateAt(5 * kMs)));
  arm::JointState bad = stateAt(20 * kMs);
  bad.q[3] = NAN;
  EXPECT_FALSE(buffer.push(bad));
  EXPECT_TRUE(buffer.push(stateAt(20 * kMs)));
  EXPECT_TRUE(buffer.push(stateAt(200 * kMs)));  // after a dropped connection
  EXPECT_EQ(buffer.size(), 3u);
  EXPECT_TRUE(buffer.jointsAt(15 * kMs));
  EXPECT_FALSE(buffer.jointsAt(100 * kMs));  // inside the gap
  EXPECT_TRUE(buffer.jointsAt(200 * kMs));
}

TEST(JointStateBuffer, DropsTheOldestWhenFull) {
  head::JointStateBufferConfig config;
  config.capacity = 8;
  head::JointStateBuffer buffer(head::HeadGeometry::example(), config);
  for (int k = 0; k < 20; ++k) buffer.push(stateAt(k * 10 * kMs));
  EXPECT_EQ(buffer.size(), 8u);
  const auto window = buffer.window();
  ASSERT_TRUE(window);
  EXPECT_EQ(window->first, 120 * kMs);
  EXPECT_EQ(window->second, 190 * kMs);
  EXPECT_FALSE(buffer.jointsAt(115 * kMs));
  EXPECT_TRUE(buffer.jointsAt(155 * kMs)->isApprox(linearJoints(155 * kMs), 1e-12));
}

TEST(JointStateBuffer, OneWriterSeveralReaders) {
  head::JointStateBufferConfig config;
  config.capacity = 64;
  head::JointStateBuffer buffer(head::HeadGeometry::example(), config);
  buffer.push(stateAt(0));
  constexpr int kSamples = 3000;
  std::atomic<bool> done{false};
  std::atomic<int> mismatches{0}, answered{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 3; ++r) {
    readers.emplace_back([&, r] {
      std::int64_t k = r;
      while (!done.load(std::memory_order_acquire)) {
        const auto window = buffer.window();
        if (!window) continue;
        // A time inside the window as seen a moment ago; it may have slid out since.
        const std::int64_t t = window->first + (k++ * 3'333'333) % (window->second - window->first + 1);
        if (const auto q = buffer.jointsAt(t)) {
          ++answered;
          if (!q->isApprox(linearJoints(t), 1e-9)) ++mismatches;
        }
        // Three readers spinning on two cores starve the writer of the reader-preferring lock
        // (5–19 s for this test); yielding keeps them overlapping the writes without that.
        std::this_thread::yield();
      }
    });
  }
  for (int k = 1; k <= kSamples; ++k) {
    EXPECT_TRUE(buffer.push(stateAt(k * 10 * kMs)));
    // Halfway, let the readers catch up so that the second half overlaps them for sure.
    if (k == kSamples / 2) {
      while (answered.load() < 3) std::this_thread::yield();
    }
  }
  done.store(true, std::memory_order_release);
  for (std::thread& t : readers) t.join();
  EXPECT_EQ(mismatches.load(), 0);
  EXPECT_GT(answered.load(), 0);
  EXPECT_EQ(buffer.window()->second, kSamples * 10 * kMs);
}

}  // namespace
}  // namespace telesphere::robot

// TrueCameraPoses (robot/stereo/true_camera_poses.h): the synthetic cameras' truth from such a buffer.
namespace telesphere::robot {
namespace {

std::array<Eigen::Isometry3d, 2> initialPoses() {
  Eigen::Isometry3d T_l = Eigen::Isometry3d::Identity(), T_r = Eigen::Isometry3d::Identity();
  T_l.translation() << 0.1, 0.2, 0.3;
  T_r.translation() << 0.16, 0.2, 0.3;
  return {T_l, T_r};
}

TEST(JointStateBuffer, AWaitingReaderIsWokenByThePushThatReachesItsTimeAndOtherwiseTimesOut) {
  head::JointStateBuffer buffer(head::HeadGeometry::example());
  ASSERT_TRUE(buffer.push(stateAt(0)));
  const auto now = [] { return std::chrono::steady_clock::now(); };
  EXPECT_TRUE(buffer.waitForSampleAtOrAfter(0, now()));  // there already: no wait
  EXPECT_FALSE(buffer.waitForSampleAtOrAfter(5 * kMs, now() + std::chrono::milliseconds(20)));  // nobody pushes
  EXPECT_EQ(buffer.waitingReaders(), 0);
  // States 1..5 ms pushed once the reader waits: it wakes with the one that reaches its time.
  std::thread writer([&buffer] {
    EXPECT_TRUE(test::eventually([&] { return buffer.waitingReaders() == 1; }));
    for (int k = 1; k <= 5; ++k) ASSERT_TRUE(buffer.push(stateAt(k * kMs)));
  });
  // A deadline an hour away: only the push's wake-up ends this wait (without it the test hangs
  // until ctest's timeout and fails).
  EXPECT_TRUE(buffer.waitForSampleAtOrAfter(5 * kMs, now() + std::chrono::hours(1)));
  writer.join();
  EXPECT_EQ(buffer.window()->second, 5 * kMs);
  EXPECT_EQ(buffer.waitingReaders(), 0);
}

TEST(TrueCameraPoses, BeforeTheArmsFirstStateTheInitialPoseIsTheTruthAndNoFallbackIsCounted) {
  const head::JointStateBuffer truth(head::HeadGeometry::example());
  const clock::SimClock clock(100 * kMs);
  const stereo::TrueCameraPoses poses(truth, clock, initialPoses(), std::chrono::milliseconds(20));
  EXPECT_TRUE(poses.at(cameras::CameraSide::kRight, 150 * kMs).isApprox(initialPoses()[1]));
  EXPECT_EQ(poses.fallbacks(), 0u);
}

TEST(TrueCameraPoses, InsideTheWindowThePoseIsTheBuffersForThatSide) {
  head::JointStateBuffer truth(head::HeadGeometry::example());
  for (int k = 0; k <= 10; ++k) ASSERT_TRUE(truth.push(stateAt(k * kMs)));
  const clock::SimClock clock(10 * kMs);
  const stereo::TrueCameraPoses poses(truth, clock, initialPoses(), std::chrono::milliseconds(20));
  for (cameras::CameraSide side : {cameras::CameraSide::kLeft, cameras::CameraSide::kRight})
    EXPECT_TRUE(poses.at(side, 4 * kMs + 500'000).isApprox(*truth.T_robot_cam(side, 4 * kMs + 500'000), 1e-12));
  EXPECT_EQ(poses.fallbacks(), 0u);
}

TEST(TrueCameraPoses, WaitsForTheSimulationToCatchUpThenFallsBackAndCountsWhenItNeverDoes) {
  head::JointStateBuffer truth(head::HeadGeometry::example());
  for (int k = 0; k <= 10; ++k) ASSERT_TRUE(truth.push(stateAt(k * kMs)));
  const clock::SimClock clock(10 * kMs);
  // An hour's patience: only the pushes' wake-ups end the wait.
  const stereo::TrueCameraPoses poses(truth, clock, initialPoses(), std::chrono::hours(1));
  // The simulation catches up with the capture time while at() waits (it pushes once at() waits,
  // one state after another, each waking the reader): the true pose, no fallback.
  std::thread writer([&truth] {
    EXPECT_TRUE(test::eventually([&] { return truth.waitingReaders() > 0; }));
    for (int k = 11; k <= 40; ++k) truth.push(stateAt(k * kMs));
  });
  const Eigen::Isometry3d T = poses.at(cameras::CameraSide::kLeft, 35 * kMs);
  writer.join();
  EXPECT_TRUE(T.isApprox(*truth.T_robot_cam(cameras::CameraSide::kLeft, 35 * kMs), 1e-12));
  EXPECT_EQ(poses.fallbacks(), 0u);
  // Far beyond what the (now stalled) simulation reached, past its extrapolation: after the wait,
  // the initial pose, counted.
  const stereo::TrueCameraPoses impatient(truth, clock, initialPoses(), std::chrono::milliseconds(20));
  EXPECT_TRUE(impatient.at(cameras::CameraSide::kLeft, 5000 * kMs).isApprox(initialPoses()[0]));
  EXPECT_EQ(impatient.fallbacks(), 1u);
}

}  // namespace
}  // namespace telesphere::robot
