// SPDX-License-Identifier: MIT
/// @brief PoseLowPassFilter: α(dt), step response, exactness for variable time steps (position
///        and rotation), −3 dB at the cut-off, and the "off" setting.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "robot/head/low_pass_filter.h"
#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot {
namespace {

Eigen::Isometry3d pose(const Eigen::Vector3d& p, double angle, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  T.translation() = p;
  return T;
}

TEST(PoseLowPassFilter, Alpha) {
  EXPECT_EQ(head::PoseLowPassFilter::alpha(100.0, 0), 0.0);
  EXPECT_NEAR(head::PoseLowPassFilter::alpha(100.0, 10'000'000), 1.0 - std::exp(-2 * M_PI), 1e-15);
  EXPECT_EQ(head::PoseLowPassFilter::alpha(std::numeric_limits<double>::infinity(), 1), 1.0);
}

TEST(PoseLowPassFilter, StepResponseFollowsTheExponential) {
  head::PoseLowPassFilter f(10.0);
  f.reset(Eigen::Isometry3d::Identity(), 0);
  const Eigen::Isometry3d target = pose({1, 0, 0}, 1.0, {0, 0, 1});
  for (int n = 1; n <= 50; ++n) {
    const Eigen::Isometry3d out = f.update(target, n * 1'000'000LL);
    const double expected = 1.0 - std::exp(-2 * M_PI * 10.0 * n * 1e-3);
    EXPECT_NEAR(out.translation().x(), expected, 1e-12);
    EXPECT_NEAR(arm::rotationLog(out.linear()).z(), expected, 1e-9);
  }
}

TEST(PoseLowPassFilter, VariableTimeStepsAreExact) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::int64_t> split(1, 9'000'000);
  const Eigen::Isometry3d start = pose({0.1, -0.2, 0.3}, 0.4, {1, 2, 3});
  const Eigen::Isometry3d target = pose({0.5, 0.1, -0.1}, 1.2, {-1, 0.5, 2});
  for (int trial = 0; trial < 20; ++trial) {
    head::PoseLowPassFilter one(100.0), many(100.0);
    one.reset(start, 0);
    many.reset(start, 0);
    const std::int64_t t_end = 30'000'000;
    const Eigen::Isometry3d a = one.update(target, t_end);
    std::int64_t t = 0;
    Eigen::Isometry3d b;
    while (t < t_end) {
      t = std::min(t_end, t + split(rng));
      b = many.update(target, t);
    }
    EXPECT_LT((a.translation() - b.translation()).norm(), 1e-12);
    EXPECT_LT(arm::rotationLog(a.linear() * b.linear().transpose()).norm(), 1e-9);
  }
}

TEST(PoseLowPassFilter, AttenuatesByThreeDecibelsAtTheCutoff) {
  const double fc = 10.0;
  head::PoseLowPassFilter f(fc);
  f.reset(Eigen::Isometry3d::Identity(), 0);
  double peak = 0;
  const std::int64_t dt_ns = 100'000;  // 10 kHz sampling ≫ f_c
  for (std::int64_t k = 1; k <= 20000; ++k) {
    const double t = static_cast<double>(k * dt_ns) * 1e-9;
    const Eigen::Isometry3d in = pose({std::sin(2 * M_PI * fc * t), 0, 0}, 0, {0, 0, 1});
    const double out = f.update(in, k * dt_ns).translation().x();
    if (t > 1.0) peak = std::max(peak, out);  // after the transient
  }
  EXPECT_NEAR(peak, 1.0 / std::sqrt(2.0), 0.01);
}

TEST(PoseLowPassFilter, OffPassesTheInputAndOlderSamplesDoNotMoveIt) {
  head::PoseLowPassFilter off(std::numeric_limits<double>::infinity());
  off.reset(Eigen::Isometry3d::Identity(), 0);
  const Eigen::Isometry3d target = pose({1, 2, 3}, 0.7, {0, 1, 0});
  EXPECT_TRUE(off.update(target, 1).isApprox(target, 1e-12));
  head::PoseLowPassFilter f(50.0);
  f.reset(Eigen::Isometry3d::Identity(), 1'000'000);
  EXPECT_TRUE(f.update(target, 500'000).isApprox(Eigen::Isometry3d::Identity(), 1e-15));
}

}  // namespace
}  // namespace telesphere::robot
