// SPDX-License-Identifier: MIT
/// @brief SimulatedArm on a driven SimClock: command latency, velocity and acceleration limits,
///        100 Hz states with seeded encoder noise, joint-limit refusal, stop and dropped-connection
///        faults.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "robot/arm/head_arm_sim.h"
#include "robot/clock/sim_clock.h"

namespace telesphere::robot {
namespace {

constexpr std::int64_t kMs = 1'000'000;

/// Advances clock and arm in 1 ms steps for `ms`, calling `each` after every step.
template <typename F>
void run(clock::SimClock& clock, arm::SimulatedArm& arm, int ms, F&& each) {
  for (int i = 0; i < ms; ++i) {
    clock.advance(kMs);
    arm.update();
    each();
  }
}

TEST(SimulatedArm, TargetsTakeEffectAfterTheCommandLatency) {
  clock::SimClock clock(5 * kMs);
  arm::SimulatedArmConfig config;
  config.command_latency_ns = 100 * kMs;
  config.encoder_noise_std = 0;
  arm::SimulatedArm arm(clock, config);
  arm::JointVector target = arm::JointVector::Zero();
  target[0] = 0.5;
  ASSERT_TRUE(arm.sendTarget(target));
  std::int64_t first_motion_ns = -1;
  run(clock, arm, 300, [&] {
    if (first_motion_ns < 0 && arm.trueJoints()[0] != 0.0) first_motion_ns = arm.simulatedUntilNs();
  });
  EXPECT_EQ(first_motion_ns, 5 * kMs + 100 * kMs + kMs);  // the first step after the set-point
}

TEST(SimulatedArm, StaticFrictionHoldsAJointAtRestUntilTheBreakaway) {
  clock::SimClock clock(0);
  arm::SimulatedArmConfig config;
  config.command_latency_ns = 0;
  config.encoder_noise_std = 0;
  config.breakaway_rad = 0.01;
  std::vector<arm::JointState> truth;
  config.on_true_state = [&](const arm::JointState& s) { truth.push_back(s); };
  arm::SimulatedArm arm(clock, config);
  arm::JointVector target = arm::JointVector::Zero();
  target[0] = 0.009;  // within the breakaway: stays put
  ASSERT_TRUE(arm.sendTarget(target));
  run(clock, arm, 100, [] {});
  EXPECT_EQ(arm.trueJoints()[0], 0.0);
  target[0] = 0.011;  // beyond it: moves, and stops on the set-point
  ASSERT_TRUE(arm.sendTarget(target));
  run(clock, arm, 300, [] {});
  EXPECT_NEAR(arm.trueJoints()[0], 0.011, 1e-9);
  // The truth hook saw every physics step, noise-free, in time order.
  ASSERT_EQ(truth.size(), 400u);
  EXPECT_EQ(truth.back().t_ns, 400 * kMs);
  EXPECT_EQ(truth.back().q, arm.trueJoints());
}

TEST(SimulatedArm, RespectsVelocityAndAccelerationLimitsAndStopsOnTarget) {
  clock::SimClock clock;
  arm::SimulatedArmConfig config;
  config.command_latency_ns = 0;
  arm::SimulatedArm arm(clock, config);
  arm::JointVector target;
  target << 1.5, -0.5, -1.0, 2.0, 1.0, -2.5;
  ASSERT_TRUE(arm.sendTarget(target));
  arm::JointVector v_prev = arm::JointVector::Zero();
  double v_seen = 0;
  run(clock, arm, 3000, [&] {
    const arm::JointVector& v = arm.trueVelocities();
    EXPECT_LE(v.cwiseAbs().maxCoeff(), config.max_velocity + 1e-12);
    EXPECT_LE((v - v_prev).cwiseAbs().maxCoeff(), config.max_acceleration * 1e-3 + 1e-12);
    v_seen = std::max(v_seen, v.cwiseAbs().maxCoeff());
    v_prev = v;
  });
  EXPECT_NEAR(v_seen, config.max_velocity, 1e-9);  // long moves reach 180°/s
  EXPECT_TRUE(arm.trueJoints().isApprox(target, 1e-12));
  EXPECT_TRUE(arm.trueVelocities().isZero(0));
}

TEST(SimulatedArm, PublishesNoisyStatesAt100HzDeterministically) {
  const auto record = [](std::uint64_t seed) {
    clock::SimClock clock;
    arm::SimulatedArmConfig config;
    config.seed = seed;
    config.q_initial = arm::JointVector::Constant(0.1);
    arm::SimulatedArm arm(clock, config);
    std::vector<arm::JointState> states;
    run(clock, arm, 1000, [&] {
      while (auto s = arm.pollState()) states.push_back(*s);
    });
    return states;
  };
  const std::vector<arm::JointState> a = record(1), b = record(1), c = record(2);
  ASSERT_EQ(a.size(), 100u);
  double sum_sq = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].t_ns, static_cast<std::int64_t>(i + 1) * 10 * kMs);
    EXPECT_EQ(a[i].q, b[i].q);
    sum_sq += (a[i].q - arm::JointVector::Constant(0.1)).squaredNorm();
  }
  EXPECT_NE(a[0].q, c[0].q);
  const double noise_std = std::sqrt(sum_sq / (6.0 * static_cast<double>(a.size())));
  EXPECT_NEAR(noise_std, arm::SimulatedArmConfig{}.encoder_noise_std, 0.2 * arm::SimulatedArmConfig{}.encoder_noise_std);
}

TEST(SimulatedArm, RefusesTargetsBeyondTheJointLimits) {
  clock::SimClock clock;
  arm::SimulatedArm arm(clock);
  arm::JointVector q = arm::JointVector::Zero();
  q[1] = 2.2;  // J2 upper limit is 120° = 2.094 rad
  EXPECT_FALSE(arm.sendTarget(q));
  q[1] = NAN;
  EXPECT_FALSE(arm.sendTarget(q));
  EXPECT_EQ(arm.refusedTargets(), 2);
  run(clock, arm, 500, [] {});
  EXPECT_TRUE(arm.trueJoints().isZero(0));
}

TEST(SimulatedArm, StopBrakesHoldsAndRefusesUntilCleared) {
  clock::SimClock clock;
  arm::SimulatedArmConfig config;
  config.command_latency_ns = 0;
  arm::SimulatedArm arm(clock, config);
  arm::JointVector target = arm::JointVector::Zero();
  target[0] = 3.0;
  ASSERT_TRUE(arm.sendTarget(target));
  run(clock, arm, 400, [] {});
  const double v_at_stop = arm.trueVelocities()[0];
  ASSERT_GT(v_at_stop, 1.0);
  arm.triggerStop();
  EXPECT_EQ(arm.status(), arm::ArmStatus::kStopped);
  EXPECT_FALSE(arm.sendTarget(arm::JointVector::Zero()));
  const double q_at_stop = arm.trueJoints()[0];
  double v_prev = v_at_stop;
  run(clock, arm, 1000, [&] {
    EXPECT_LE(std::abs(arm.trueVelocities()[0] - v_prev), config.max_acceleration * 1e-3 + 1e-12);
    v_prev = arm.trueVelocities()[0];
  });
  EXPECT_EQ(arm.trueVelocities()[0], 0.0);
  // Braking distance v²/(2a), give or take one step.
  EXPECT_NEAR(arm.trueJoints()[0] - q_at_stop, v_at_stop * v_at_stop / (2 * config.max_acceleration),
              0.01);
  arm::JointState last;
  while (auto s = arm.pollState()) last = *s;
  EXPECT_EQ(last.status, arm::ArmStatus::kStopped);
  EXPECT_TRUE(arm.clearStop());
  EXPECT_TRUE(arm.sendTarget(arm::JointVector::Zero()));
  run(clock, arm, 3000, [] {});
  EXPECT_NEAR(arm.trueJoints()[0], 0.0, 1e-12);
}

TEST(SimulatedArm, DroppedConnectionLosesStatesAndTargets) {
  clock::SimClock clock;
  arm::SimulatedArmConfig config;
  config.command_latency_ns = 100 * kMs;
  arm::SimulatedArm arm(clock, config);
  arm::JointVector target = arm::JointVector::Zero();
  target[5] = 1.0;
  ASSERT_TRUE(arm.sendTarget(target));
  run(clock, arm, 50, [] {});
  arm.dropConnection();  // the target is still in flight: lost
  EXPECT_EQ(arm.status(), arm::ArmStatus::kDisconnected);
  EXPECT_FALSE(arm.sendTarget(target));
  EXPECT_FALSE(arm.clearStop());
  int received = 0;
  run(clock, arm, 500, [&] {
    while (arm.pollState()) ++received;
  });
  EXPECT_EQ(received, 0);
  EXPECT_EQ(arm.trueJoints()[5], 0.0);
  arm.reconnect();
  EXPECT_EQ(arm.status(), arm::ArmStatus::kOk);
  run(clock, arm, 100, [&] {
    while (arm.pollState()) ++received;
  });
  EXPECT_GT(received, 0);
  EXPECT_TRUE(arm.sendTarget(target));
}

}  // namespace
}  // namespace telesphere::robot
