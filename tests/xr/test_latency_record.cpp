// SPDX-License-Identifier: MIT
/// @brief LatencyRecord (xr/video/latency_record.h): up to its capacity the figures are
///        latencyFigure's to the digit; beyond, on two million seeded log-normal samples, within
///        0.5 % of the nearest-rank value while the memory it holds stays what it was at the
///        capacity; at the extremes (zeros, negative, sub-microsecond, beyond the histogram, infinite,
///        all equal, NaN) the figures stay within the samples' range and NaN is not counted.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "xr/video/latency_record.h"

namespace telesphere::xr::video {
namespace {

TEST(LatencyRecord, UpToItsCapacityTheFiguresAreExact) {
  std::mt19937 rng(35);
  std::lognormal_distribution<double> ms(1.0, 0.6);
  LatencyRecord record(5000);
  std::vector<double> all;
  for (int i = 0; i < 5000; ++i) {
    all.push_back(ms(rng));
    record.add(all.back());
    if (i % 997 == 0 || i == 4999) {
      const LatencyFigure want = latencyFigure(all), got = record.figure();
      ASSERT_EQ(got.n, want.n);
      ASSERT_EQ(got.p50_ms, want.p50_ms) << i;
      ASSERT_EQ(got.p99_ms, want.p99_ms) << i;
    }
  }
}

TEST(LatencyRecord, BeyondItsCapacityMemoryStaysAndTheFiguresAreWithinHalfAPercent) {
  std::mt19937 rng(2026);
  std::lognormal_distribution<double> ms(1.5, 0.8);  // a render time's tail: p99 ~ 30 ms
  LatencyRecord record(1000);
  std::vector<double> all;
  std::size_t held_at_capacity = 0;
  for (int i = 0; i < 2'000'000; ++i) {
    all.push_back(ms(rng));
    record.add(all.back());
    if (i == 999) held_at_capacity = record.bytesHeld();
  }
  EXPECT_EQ(record.bytesHeld(), held_at_capacity);
  EXPECT_LT(held_at_capacity, 40'000u);  // 1000 samples and ~2100 bins, against 16 MB for all of them
  const LatencyFigure want = latencyFigure(all), got = record.figure();
  EXPECT_EQ(got.n, 2'000'000u);
  EXPECT_NEAR(got.p50_ms, want.p50_ms, 0.005 * want.p50_ms);
  EXPECT_NEAR(got.p99_ms, want.p99_ms, 0.005 * want.p99_ms);
}

TEST(LatencyRecord, AtTheExtremesTheFiguresStayWithinTheSamples) {
  // All equal, beyond the capacity: the bin's middle is clamped to the one value.
  LatencyRecord same(10);
  for (int i = 0; i < 100; ++i) same.add(11.1);
  EXPECT_EQ(same.figure().p50_ms, 11.1);
  EXPECT_EQ(same.figure().p99_ms, 11.1);
  // Zeros and negative values (a clock step) below the histogram, huge and infinite ones above it.
  LatencyRecord edges(4);
  for (int i = 0; i < 60; ++i) edges.add(0.0);
  for (int i = 0; i < 30; ++i) edges.add(-5.0);
  for (int i = 0; i < 8; ++i) edges.add(1e-9);
  edges.add(1e9);
  edges.add(std::numeric_limits<double>::infinity());
  edges.add(std::numeric_limits<double>::quiet_NaN());  // not counted
  const LatencyFigure f = edges.figure();
  EXPECT_EQ(f.n, 100u);
  EXPECT_GE(f.p50_ms, -5.0);
  EXPECT_LE(f.p50_ms, 1e-3 * 1.01);  // in the lowest bin, where the 50th of 100 lies
  EXPECT_TRUE(std::isfinite(f.p50_ms));
  EXPECT_GT(f.p99_ms, 0.99e6);  // the 99th of 100 (1e9) counts in the highest bin, up to 1e6
  // Nothing added: n = 0, figures 0 (as latencyFigure).
  const LatencyFigure none = LatencyRecord().figure();
  EXPECT_EQ(none.n, 0u);
  EXPECT_EQ(none.p50_ms, 0.0);
}

}  // namespace
}  // namespace telesphere::xr::video
