// SPDX-License-Identifier: MIT
/// @brief InverseDepthFilter on simulated sequences of one tile's inverse depth at 30 Hz: a large
///        step snaps at once, a small one settles with the time constant and the rate limit
///        without overshoot; a ramp is followed with a bounded lag; seeded noise shrinks; a filled
///        (unconfident) tile moves slower than a matched one; time going backwards or another
///        tiling restarts the filter.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "xr/depth/inverse_depth_filter.h"

namespace telesphere::xr {
namespace {

constexpr std::int64_t kFrameNs = 33'333'333;  // 30 Hz

/// A 10° grid (18 × 36 tiles) of one value, all matched (confidence 1) unless told otherwise.
struct Frame {
  render::InverseDepthGrid grid{10.0};
  std::vector<float> confidence = std::vector<float>(18 * 36, 1.0F);
  explicit Frame(double rho) : grid(10.0, static_cast<float>(rho)) {}
};

TEST(InverseDepthFilter, ALargeStepSnapsAndASmallOneSettlesWithoutOvershoot) {
  depth::InverseDepthFilter filter;
  std::int64_t t = 0;
  for (int i = 0; i < 30; ++i, t += kFrameNs) filter.update(Frame(0.33).grid, Frame(0.33).confidence, t);
  // A near object arrives (0.33 → 2.5 1/m): taken in the same frame.
  const Frame near(2.5);
  EXPECT_FLOAT_EQ(filter.update(near.grid, near.confidence, t).at(9, 18), 2.5F);
  EXPECT_EQ(filter.snapped(), 18 * 36);
  // A small step (2.5 → 2.7, below the snap of 0.25): 63 % after one time constant (rate limit
  // 4 1/m/s does not bind), never past the target, within 1 % after a second.
  const Frame further(2.7);
  double value = 2.5;
  for (int i = 1; i <= 30; ++i) {
    t += kFrameNs;
    value = filter.update(further.grid, further.confidence, t).at(9, 18);
    EXPECT_LE(value, 2.7 + 1e-6);
    if (i == 5) {
      EXPECT_NEAR(value, 2.5 + 0.2 * (1 - std::exp(-5 * 0.0333333 / 0.15)), 0.005) << "after 5 frames";
    }
  }
  EXPECT_NEAR(value, 2.7, 0.003);
  EXPECT_EQ(filter.snapped(), 0);
}

TEST(InverseDepthFilter, TheRateLimitBoundsEachFramesStep) {
  depth::InverseDepthFilterOptions options;
  options.max_rate_per_m_s = 0.6;  // 0.02 1/m a frame
  options.time_constant_s = 0.01;  // the average alone would jump there
  depth::InverseDepthFilter filter(options);
  filter.update(Frame(1.0).grid, Frame(1.0).confidence, 0);
  const Frame target(1.2);  // below the snap
  const double v1 = filter.update(target.grid, target.confidence, kFrameNs).at(0, 0);
  EXPECT_NEAR(v1 - 1.0, 0.02, 1e-4);
  const double v2 = filter.update(target.grid, target.confidence, 2 * kFrameNs).at(0, 0);
  EXPECT_NEAR(v2 - v1, 0.02, 1e-4);
}

TEST(InverseDepthFilter, ARampIsFollowedWithABoundedLag) {
  // An object approaching: inverse depth rising 1 1/m a second (from 1 to 3 in 2 s).
  depth::InverseDepthFilter filter;
  double lag = 0;
  for (int i = 0; i <= 60; ++i) {
    const double truth = 1.0 + i / 30.0;
    const Frame f(truth);
    const double value = filter.update(f.grid, f.confidence, i * kFrameNs).at(5, 5);
    lag = truth - value;
    EXPECT_GE(lag, -1e-6);  // never ahead
  }
  // Steady lag of a first-order filter on a ramp: rate × τ (1 × 0.15), discretely a little more.
  EXPECT_NEAR(lag, 0.15, 0.03);
}

TEST(InverseDepthFilter, AnObjectClosingFastIsTakenAtEachSweep) {
  // A cube closing at 0.5 m/s inside 0.4 m, swept at 10 Hz: its inverse depth jumps 0.3 1/m a
  // sweep. Each jump is taken at once (with a snap at 0.5 1/m the filter lagged 0.3–0.6 1/m behind,
  // 2–4° for a head 6 cm aside: telesphere-bench depth, the approaching object).
  depth::InverseDepthFilter filter;
  double lag = 0;
  for (int i = 0; i <= 8; ++i) {
    const double truth = 1.0 + 0.3 * i;
    const Frame f(truth);
    lag = truth - filter.update(f.grid, f.confidence, i * 100'000'000LL).at(9, 18);
  }
  EXPECT_LT(std::abs(lag), 1e-6) << "lag " << lag << " 1/m";
}

TEST(InverseDepthFilter, SeededNoiseShrinks) {
  std::mt19937 rng(35);
  std::uniform_real_distribution<double> noise(-0.1, 0.1);  // below the snap
  depth::InverseDepthFilter filter;
  double raw2 = 0, filtered2 = 0;
  int n = 0;
  for (int i = 0; i < 300; ++i) {
    const double measured = 1.0 + noise(rng);
    const Frame f(measured);
    const double value = filter.update(f.grid, f.confidence, i * kFrameNs).at(3, 7);
    if (i < 30) continue;  // settled
    raw2 += (measured - 1.0) * (measured - 1.0);
    filtered2 += (value - 1.0) * (value - 1.0);
    ++n;
  }
  const double raw_rms = std::sqrt(raw2 / n), filtered_rms = std::sqrt(filtered2 / n);
  EXPECT_LT(filtered_rms, 0.5 * raw_rms) << raw_rms << " → " << filtered_rms;
}

TEST(InverseDepthFilter, FilledTilesMoveSlowerThanMatchedOnes) {
  depth::InverseDepthFilter filter;
  filter.update(Frame(1.0).grid, Frame(1.0).confidence, 0);
  Frame f(1.2);  // below the snap
  f.confidence[0] = 0.0F;  // tile (0, 0) was filled from its neighbours, not matched
  double matched = 0, filled = 0;
  for (int i = 1; i <= 9; ++i) {
    const render::InverseDepthGrid& g = filter.update(f.grid, f.confidence, i * kFrameNs);
    matched = g.at(0, 1);
    filled = g.at(0, 0);
  }
  EXPECT_GT(matched - 1.0, 0.8 * 0.2);  // 0.3 s = 2 time constants
  EXPECT_LT(filled - 1.0, 0.5 * (matched - 1.0));
  EXPECT_GT(filled, 1.0);
  // A filled tile never snaps, however far it is.
  Frame far_off(5.0);
  far_off.confidence.assign(far_off.confidence.size(), 0.0F);
  filter.update(far_off.grid, far_off.confidence, 10 * kFrameNs);
  EXPECT_EQ(filter.snapped(), 0);
}

TEST(InverseDepthFilter, TimeGoingBackwardsOrANewTilingRestarts) {
  depth::InverseDepthFilter filter;
  EXPECT_FALSE(filter.current());
  filter.update(Frame(1.0).grid, Frame(1.0).confidence, 10 * kFrameNs);
  EXPECT_FLOAT_EQ(filter.update(Frame(1.3).grid, Frame(1.3).confidence, 5 * kFrameNs).at(0, 0), 1.3F);
  const render::InverseDepthGrid other(5.0, 0.7F);
  const std::vector<float> confidence(36 * 72, 1.0F);
  const render::InverseDepthGrid& g = filter.update(other, confidence, 6 * kFrameNs);
  EXPECT_EQ(g.rows(), 36);
  EXPECT_FLOAT_EQ(g.at(0, 0), 0.7F);
}

}  // namespace
}  // namespace telesphere::xr
