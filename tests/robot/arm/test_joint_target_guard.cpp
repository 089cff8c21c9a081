// SPDX-License-Identifier: MIT
/// @brief JointTargetGuard, the arm driver's jump and limit rule, without a socket: steps at the
///        top speed pass, steps beyond it are refused, N in a row are a fault naming the joint, the
///        time since the last target counts only between one and three periods, and non-finite or
///        out-of-limit targets never pass (at the extremes too).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "robot/arm/joint_target_guard.h"

namespace telesphere::robot {
namespace {

constexpr std::int64_t kPeriod = 10'000'000;  // 10 ms
constexpr double kTop = M_PI;                  // rad/s
using V = arm::JointTargetGuard::Verdict;

arm::JointTargetGuard started(const arm::JointVector& q, std::int64_t t = 0, int n = 10) {
  arm::JointTargetGuard g({kTop, kPeriod, n});
  g.startFrom(q, t);
  return g;
}

arm::JointVector home() { return (arm::JointVector() << 0, -0.3, -0.5, 0, 0.8, 0).finished(); }

TEST(JointTargetGuard, StepsUpToTheTopSpeedPassAndBecomeTheReference) {
  arm::JointTargetGuard g = started(home());
  arm::JointVector q = home();
  for (int k = 1; k <= 50; ++k) {  // J2 from −17° to 72°
    q[1] += 0.99 * kTop * 0.01;  // just under π rad/s for 10 ms
    ASSERT_EQ(g.check(q, k * kPeriod), V::kAccepted) << k;
  }
  EXPECT_TRUE(g.reference()->isApprox(q));
  EXPECT_EQ(g.consecutiveJumps(), 0);
}

TEST(JointTargetGuard, AStepBeyondTheTopSpeedIsRefusedAndTheReferenceStays) {
  arm::JointTargetGuard g = started(home());
  arm::JointVector q = home();
  q[2] += kTop * 0.01 + 0.01;  // 10 mrad more than 10 ms allow (tolerance 1 mrad)
  EXPECT_EQ(g.check(q, kPeriod), V::kJump);
  EXPECT_TRUE(g.reference()->isApprox(home()));
  EXPECT_EQ(g.consecutiveJumps(), 1);
  // Back within reach of the reference: accepted, the count restarts.
  EXPECT_EQ(g.check(home(), 2 * kPeriod), V::kAccepted);
  EXPECT_EQ(g.consecutiveJumps(), 0);
}

TEST(JointTargetGuard, TenJumpsInARowAreAFaultThatNamesTheJointAndTheLimit) {
  arm::JointTargetGuard g = started(home());
  arm::JointVector far = home();
  far[1] += 45 * M_PI / 180;
  for (int k = 1; k < 10; ++k) ASSERT_EQ(g.check(far, k * kPeriod), V::kJump) << k;
  EXPECT_EQ(g.check(far, 10 * kPeriod), V::kJumpFault);
  EXPECT_NE(g.fault().find("J2 by 45°"), std::string::npos) << g.fault();
  // Measured from the last accepted target, at most three periods: 30 ms, π rad/s → 5°.
  EXPECT_NE(g.fault().find("in 30 ms"), std::string::npos) << g.fault();
  EXPECT_NE(g.fault().find("allows 5°"), std::string::npos) << g.fault();
}

TEST(JointTargetGuard, AnAcceptedTargetBetweenJumpsRestartsTheCount) {
  arm::JointTargetGuard g = started(home(), 0, 3);
  arm::JointVector far = home();
  far[0] += 1.0;
  std::int64_t t = 0;
  for (int round = 0; round < 5; ++round) {
    EXPECT_EQ(g.check(far, t += kPeriod), V::kJump);
    EXPECT_EQ(g.check(far, t += kPeriod), V::kJump);
    EXPECT_EQ(g.check(home(), t += kPeriod), V::kAccepted);
  }
  EXPECT_EQ(g.check(far, t += kPeriod), V::kJump);
  EXPECT_EQ(g.check(far, t += kPeriod), V::kJump);
  EXPECT_EQ(g.check(far, t += kPeriod), V::kJumpFault);
}

TEST(JointTargetGuard, TheTimeSinceCountsBetweenOneAndThreePeriods) {
  const double one_period = kTop * 0.01;
  // A long silence does not allow a long step: at most three periods' worth.
  arm::JointTargetGuard g = started(home());
  arm::JointVector q = home();
  q[3] += 3 * one_period - 0.0005;
  EXPECT_EQ(g.check(q, 1'000'000'000), V::kAccepted);  // 1 s later, 3 periods' step
  q[3] += 3 * one_period + 0.005;
  EXPECT_EQ(g.check(q, 3'000'000'000), V::kJump);  // 2 s later, a bit more than 3 periods' step
  // An early tick (1 ms after) still allows one period's step.
  arm::JointTargetGuard h = started(home());
  arm::JointVector r = home();
  r[4] += one_period - 0.0005;
  EXPECT_EQ(h.check(r, 1'000'000), V::kAccepted);
}

TEST(JointTargetGuard, NonFiniteAndOutOfLimitTargetsNeverPassAndDoNotCountAsJumps) {
  arm::JointTargetGuard g = started(home());
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity(), 1e300}) {
    for (int j = 0; j < 6; ++j) {
      arm::JointVector q = home();
      q[j] = bad;
      EXPECT_EQ(g.check(q, kPeriod), V::kOutsideLimits) << "joint " << j << " = " << bad;
    }
  }
  arm::JointVector beyond = home();
  beyond[1] = 121 * M_PI / 180;  // J2's limit is 120°
  EXPECT_EQ(g.check(beyond, kPeriod), V::kOutsideLimits);
  EXPECT_EQ(g.consecutiveJumps(), 0);
  EXPECT_EQ(g.check(home(), kPeriod), V::kAccepted);
}

TEST(JointTargetGuard, WithoutAReferenceAnyTargetWithinLimitsPassesThenTheRuleHolds) {
  arm::JointTargetGuard g({kTop, kPeriod, 10});
  EXPECT_EQ(g.check(home(), 0), V::kAccepted);
  arm::JointVector far = home();
  far[5] += 1.0;
  EXPECT_EQ(g.check(far, kPeriod), V::kJump);
}

TEST(JointTargetGuard, SeededRandomStepsAreJudgedByTheirLargestJoint) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> step(-0.05, 0.05);
  arm::JointTargetGuard g = started(home());
  arm::JointVector ref = home();
  std::int64_t t = 0;
  int accepted = 0, refused = 0;
  for (int k = 0; k < 2000; ++k) {
    arm::JointVector q = ref;
    for (int j = 0; j < 6; ++j) q[j] += step(rng);
    t += kPeriod;
    const double largest = (q - ref).cwiseAbs().maxCoeff();
    const V v = g.check(q, t);
    if (largest > kTop * 0.01 + 1e-3) {
      ASSERT_NE(v, V::kAccepted) << k;
      ++refused;
      // the next target's time since is then the two periods since the reference
      g.startFrom(ref, t);
    } else {
      ASSERT_EQ(v, V::kAccepted) << k;
      ref = q;
      ++accepted;
    }
  }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(refused, 100);
}

}  // namespace
}  // namespace telesphere::robot
