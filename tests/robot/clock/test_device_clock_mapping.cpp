// SPDX-License-Identifier: MIT
/// @brief DeviceClockMapping on synthetic (hardware stamp, host arrival) pairs with known offset,
///        50 ppm drift, a fixed minimum delay and exponential arrival jitter: the recovered mapping
///        is far tighter than the jitter (and than a least-squares fit); clock jumps reset it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "robot/clock/device_clock_mapping.h"

namespace telesphere::robot {
namespace {

/// A camera clock that runs (1 − drift) as fast as the host's: host = host0 + (hw − hw0)·(1 + drift).
struct SyntheticClocks {
  std::int64_t hw0_ns = 1'795'363'058'805'212'000;  // camera clocks often count from the epoch
  std::int64_t host0_ns = 10'179'717'063'418;       // steady clock: time since boot
  double drift_ppm = 50.0;
  std::int64_t min_delay_ns = 800'000;  // stamp latch → earliest host arrival
  double jitter_mean_ns = 2'000'000;    // exponential: transfer, interrupts, scheduling

  std::int64_t hostOf(std::int64_t hw_ns) const {
    const std::int64_t dx = hw_ns - hw0_ns;
    return host0_ns + dx + std::llround(static_cast<double>(dx) * drift_ppm * 1e-6);
  }
};

constexpr std::int64_t kFramePeriodNs = 22'222'222;  // 45 Hz

TEST(DeviceClockMapping, LowerEnvelopeRecoversOffsetAndDriftFarBelowTheJitter) {
  SyntheticClocks clocks;
  std::mt19937_64 rng(20261122);
  std::exponential_distribution<double> jitter(1.0 / clocks.jitter_mean_ns);
  clock::DeviceClockMapping mapping;  // window 512 (~11 s at 45 Hz)

  double max_error_ns = 0, sum_error_ns = 0;
  int checked = 0;
  // Least-squares reference over the same window, to show what the envelope buys.
  std::vector<std::pair<double, double>> recent;
  double max_lsq_error_ns = 0;
  for (int i = 0; i < 45 * 60; ++i) {  // one minute
    const std::int64_t hw_ns = clocks.hw0_ns + i * kFramePeriodNs;
    const std::int64_t arrival_ns =
        clocks.hostOf(hw_ns) + clocks.min_delay_ns + std::llround(jitter(rng));
    ASSERT_NE(mapping.add(hw_ns, arrival_ns), clock::DeviceClockMapping::AddResult::kReset) << "frame " << i;
    recent.emplace_back(static_cast<double>(hw_ns - clocks.hw0_ns), static_cast<double>(arrival_ns - clocks.host0_ns));
    if (recent.size() > 512) recent.erase(recent.begin());
    if (i < 600) continue;  // window filled
    const double error_ns = static_cast<double>(mapping.toHostNs(hw_ns) - (clocks.hostOf(hw_ns) + clocks.min_delay_ns));
    max_error_ns = std::max(max_error_ns, std::abs(error_ns));
    sum_error_ns += error_ns;
    ++checked;
    double mx = 0, my = 0;
    for (auto [x, y] : recent) mx += x, my += y;
    mx /= recent.size(), my /= recent.size();
    double sxx = 0, sxy = 0;
    for (auto [x, y] : recent) sxx += (x - mx) * (x - mx), sxy += (x - mx) * (y - my);
    const double lsq = my + sxy / sxx * (static_cast<double>(hw_ns - clocks.hw0_ns) - mx);
    max_lsq_error_ns = std::max(max_lsq_error_ns,
                                std::abs(lsq - static_cast<double>(clocks.hostOf(hw_ns) + clocks.min_delay_ns - clocks.host0_ns)));
  }
  // Jitter mean 2 ms: the envelope stays within 100 µs (1/20 of it) at the newest frame, where it
  // is used (extrapolating half a window from the fit's centre); least squares is off by ~the mean.
  EXPECT_LT(max_error_ns, 100'000.0);
  EXPECT_GT(max_lsq_error_ns, 1'000'000.0);
  EXPECT_NEAR(sum_error_ns / checked, 0.0, 30'000.0);
  EXPECT_NEAR(mapping.driftPpm(), clocks.drift_ppm, 3.0);
  const std::int64_t last_hw = clocks.hw0_ns + (45 * 60 - 1) * kFramePeriodNs;
  EXPECT_NEAR(static_cast<double>(mapping.hwToHostOffsetNs()),
              static_cast<double>(clocks.hostOf(last_hw) + clocks.min_delay_ns - last_hw), 50'000.0);
  EXPECT_EQ(mapping.size(), 512u);
  EXPECT_EQ(mapping.jumps(), 0u);
  std::printf("clock mapping: max |error| %.1f us, mean error %.1f us, least squares max %.0f us, drift %.2f ppm\n",
              max_error_ns / 1e3, sum_error_ns / checked / 1e3, max_lsq_error_ns / 1e3, mapping.driftPpm());
}

TEST(DeviceClockMapping, OnePairMapsWithUnitSlopeAndShortWindowsBoundTheDrift) {
  clock::DeviceClockMappingOptions options;
  options.max_drift_ppm = 200;
  clock::DeviceClockMapping mapping(options);
  EXPECT_FALSE(mapping.valid());
  mapping.add(1'000'000'000, 5'000'000'000);
  ASSERT_TRUE(mapping.valid());
  EXPECT_EQ(mapping.toHostNs(1'000'000'000), 5'000'000'000);
  EXPECT_EQ(mapping.toHostNs(1'010'000'000), 5'010'000'000);
  EXPECT_EQ(mapping.hwToHostOffsetNs(), 4'000'000'000);
  // Second pair 20 ms later but 3 ms later in arrival: the raw slope (15 %) is clamped to 200 ppm.
  mapping.add(1'020'000'000, 5'023'000'000);
  EXPECT_NEAR(mapping.driftPpm(), 200.0, 1e-6);
  EXPECT_LE(mapping.toHostNs(1'000'000'000), 5'000'000'000);  // every pair on or above the line
  EXPECT_LE(mapping.toHostNs(1'020'000'000), 5'023'000'000);
}

TEST(DeviceClockMapping, ClockJumpsResetTheFitAndItRecovers) {
  SyntheticClocks clocks;
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> jitter(1.0 / clocks.jitter_mean_ns);
  clock::DeviceClockMapping mapping;
  std::int64_t hw_ns = clocks.hw0_ns;
  std::int64_t host_shift_ns = 0;  // how far the camera clock has jumped, host unchanged
  auto arrival = [&](std::int64_t hw) { return clocks.hostOf(hw - host_shift_ns) + clocks.min_delay_ns + std::llround(jitter(rng)); };
  auto settled = [&](std::int64_t hw) {
    return std::abs(static_cast<double>(mapping.toHostNs(hw) - (clocks.hostOf(hw - host_shift_ns) + clocks.min_delay_ns)));
  };
  for (int i = 0; i < 300; ++i, hw_ns += kFramePeriodNs) mapping.add(hw_ns, arrival(hw_ns));
  EXPECT_LT(settled(hw_ns), 100'000.0);

  // A single very late arrival (a 300 ms stall) is skipped, not a jump.
  EXPECT_EQ(mapping.add(hw_ns, clocks.hostOf(hw_ns) + 300'000'000), clock::DeviceClockMapping::AddResult::kLateSkipped);
  hw_ns += kFramePeriodNs;
  EXPECT_EQ(mapping.add(hw_ns, arrival(hw_ns)), clock::DeviceClockMapping::AddResult::kAdded);
  EXPECT_EQ(mapping.jumps(), 0u);

  // The camera clock restarts from a small value (camera reset): stamps go back → reset.
  host_shift_ns = 1'000'000'000 - (hw_ns + kFramePeriodNs);  // true time goes on one frame later
  hw_ns = 1'000'000'000;
  EXPECT_EQ(mapping.add(hw_ns, arrival(hw_ns)), clock::DeviceClockMapping::AddResult::kReset);
  EXPECT_EQ(mapping.jumps(), 1u);
  EXPECT_EQ(mapping.size(), 1u);
  for (int i = 0; i < 300; ++i) {
    hw_ns += kFramePeriodNs;
    ASSERT_EQ(mapping.add(hw_ns, arrival(hw_ns)), clock::DeviceClockMapping::AddResult::kAdded) << i;
  }
  EXPECT_LT(settled(hw_ns), 100'000.0);

  // The camera clock jumps forward by 2 s: pairs would land 2 s before the fit → reset.
  host_shift_ns += 2'000'000'000;
  hw_ns += kFramePeriodNs + 2'000'000'000;
  EXPECT_EQ(mapping.add(hw_ns, arrival(hw_ns)), clock::DeviceClockMapping::AddResult::kReset);
  EXPECT_EQ(mapping.jumps(), 2u);

  // The camera clock steps back by 10 ms only (less than a frame): stamps still increase, every
  // pair now arrives "late" by 10 ms … below the threshold it just widens the envelope; by 100 ms
  // (threshold 50 ms), after late_pairs_for_reset pairs the fit resets.
  for (int i = 0; i < 100; ++i) {
    hw_ns += kFramePeriodNs;
    mapping.add(hw_ns, arrival(hw_ns));
  }
  host_shift_ns -= 100'000'000;
  hw_ns += kFramePeriodNs - 100'000'000 + kFramePeriodNs * 5;  // still increasing
  int late = 0;
  clock::DeviceClockMapping::AddResult result = clock::DeviceClockMapping::AddResult::kAdded;
  for (int i = 0; i < 10 && result != clock::DeviceClockMapping::AddResult::kReset; ++i) {
    hw_ns += kFramePeriodNs;
    result = mapping.add(hw_ns, arrival(hw_ns));
    late += result == clock::DeviceClockMapping::AddResult::kLateSkipped;
  }
  EXPECT_EQ(result, clock::DeviceClockMapping::AddResult::kReset);
  EXPECT_EQ(late, clock::DeviceClockMappingOptions{}.late_pairs_for_reset - 1);
  EXPECT_EQ(mapping.jumps(), 3u);

  mapping.reset();
  EXPECT_FALSE(mapping.valid());
  EXPECT_EQ(mapping.jumps(), 3u);
}

}  // namespace
}  // namespace telesphere::robot
