// SPDX-License-Identifier: MIT
/// @brief DelayTrendDetector on simulated paths (app/bench/impairment): quiet below capacity, over-use
///        within a few hundred ms when the sender exceeds the bottleneck, under-use while the
///        queue drains, deaf to jitter without a queue, to loss and to the clocks' offset; the
///        slope of a known ramp recovered.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "app/bench/impairment/impaired_path.h"
#include "robot/link/delay_trend.h"

namespace telesphere::link {
namespace {

using bench::impairment::ImpairedPath;
using bench::impairment::PathOptions;
using bench::impairment::RateTrace;

constexpr std::int64_t kMs = 1'000'000;

struct PathRun {
  std::vector<std::pair<std::int64_t, PathUsage>> usage;  ///< (arrival ns, usage after it)
  int overuse = 0, underuse = 0;
  std::optional<std::int64_t> first_overuse_ns, first_underuse_ns;
};

/// 1200-byte packets through `path`, sent every `interval_ns(t)` until end_ns; the detector sees
/// them as they arrive (arrival clock offset by `clock_offset_ns`).
template <class Interval>
PathRun simulate(PathOptions options, Interval interval_ns, std::int64_t end_ns, std::int64_t clock_offset_ns = 0) {
  ImpairedPath path(std::move(options));
  DelayTrendDetector detector;
  PathRun run;
  for (std::int64_t t = 0; t < end_ns; t += interval_ns(t)) {
    path.offer(std::vector<std::uint8_t>(1200), t);
    for (const auto& packet : path.arrivedBy(t)) {
      const PathUsage u = detector.onPacket(packet.offered_ns, packet.arrives_ns + clock_offset_ns);
      run.usage.emplace_back(packet.arrives_ns, u);
      if (u == PathUsage::kOveruse) {
        ++run.overuse;
        if (!run.first_overuse_ns) run.first_overuse_ns = packet.arrives_ns;
      }
      if (u == PathUsage::kUnderuse) {
        ++run.underuse;
        if (!run.first_underuse_ns) run.first_underuse_ns = packet.arrives_ns;
      }
    }
  }
  return run;
}

TEST(DelayTrendDetector, BelowCapacityStaysNormal) {
  PathOptions options;
  options.rate = RateTrace::constant(20e6);  // sending 9.6 Mbit/s
  options.one_way_delay_ns = 50 * kMs;
  const PathRun run = simulate(options, [](std::int64_t) { return kMs; }, 5000 * kMs);
  EXPECT_GT(run.usage.size(), 4900u);
  EXPECT_EQ(run.overuse, 0);
}

TEST(DelayTrendDetector, AboveCapacityIsOveruseWithinAFewHundredMs) {
  PathOptions options;
  options.rate = RateTrace::constant(8e6);  // 9.6 Mbit/s into 8: the queue grows 0.2 ms per ms
  options.one_way_delay_ns = 50 * kMs;
  options.queue_limit_bytes = 10 << 20;
  const PathRun run = simulate(options, [](std::int64_t) { return kMs; }, 2000 * kMs);
  ASSERT_TRUE(run.first_overuse_ns);
  std::printf("first over-use at %.1f ms, %d of %zu packets\n", *run.first_overuse_ns / 1e6, run.overuse, run.usage.size());
  EXPECT_LT(*run.first_overuse_ns, 400 * kMs) << "first over-use at " << *run.first_overuse_ns / kMs << " ms";
  EXPECT_GT(run.overuse, static_cast<int>(run.usage.size()) / 2);
}

TEST(DelayTrendDetector, ADrainingQueueIsUnderuse) {
  PathOptions options;
  options.rate = RateTrace::constant(8e6);
  options.one_way_delay_ns = 50 * kMs;
  options.queue_limit_bytes = 10 << 20;
  // 1 s at 9.6 Mbit/s builds 200 ms of queue; then 4.8 Mbit/s drains it in about 0.5 s.
  const PathRun run = simulate(options, [](std::int64_t t) { return t < 1000 * kMs ? kMs : 2 * kMs; }, 3000 * kMs);
  ASSERT_TRUE(run.first_underuse_ns);
  std::printf("first under-use at %.1f ms\n", *run.first_underuse_ns / 1e6);
  EXPECT_GT(*run.first_underuse_ns, 1000 * kMs);
  EXPECT_LT(*run.first_underuse_ns, 1600 * kMs);
  // Once drained, normal again: the last half second has no under-use.
  for (const auto& [t, u] : run.usage) {
    if (t > 2500 * kMs) {
      EXPECT_NE(u, PathUsage::kUnderuse) << t / kMs << " ms";
    }
  }
}

TEST(DelayTrendDetector, JitterAndLossWithoutAQueueAreNotOveruse) {
  PathOptions options;
  options.one_way_delay_ns = 50 * kMs;
  options.jitter_ns = 2 * kMs;
  options.loss = {0.05, 2, 3};
  const PathRun run = simulate(options, [](std::int64_t) { return kMs; }, 10'000 * kMs);
  EXPECT_LT(run.overuse, static_cast<int>(run.usage.size()) / 100) << run.overuse << " of " << run.usage.size();
}

TEST(DelayTrendDetector, TheClocksOffsetCancels) {
  PathOptions options;
  options.rate = RateTrace::constant(8e6);
  options.one_way_delay_ns = 50 * kMs;
  options.queue_limit_bytes = 10 << 20;
  const auto every_ms = [](std::int64_t) { return kMs; };
  const PathRun a = simulate(options, every_ms, 1000 * kMs);
  const PathRun b = simulate(options, every_ms, 1000 * kMs, 1'000'000'000'000);
  ASSERT_EQ(a.usage.size(), b.usage.size());
  for (std::size_t i = 0; i < a.usage.size(); ++i) EXPECT_EQ(a.usage[i].second, b.usage[i].second) << i;
}

TEST(DelayTrendDetector, RecoversTheSlopeOfAKnownRamp) {
  DelayTrendDetector detector;
  // The queue grows by 0.1 ms per ms of arrival: packets every 6 ms (one per group), each
  // delayed 0.6 ms more than the one before.
  for (int i = 0; i < 300; ++i) detector.onPacket(i * 6 * kMs, i * 6 * kMs + i * 600'000);
  ASSERT_TRUE(detector.slope());
  // Arrivals are 6.6 ms apart: 0.6 ms more delay per 6.6 ms of arrival time.
  EXPECT_NEAR(*detector.slope(), 0.6 / 6.6, 1e-3);
  EXPECT_EQ(detector.usage(), PathUsage::kOveruse);
}

TEST(DelayTrendDetector, BadOptionsAreNamed) {
  DelayTrendOptions o;
  EXPECT_TRUE(checkDelayTrendOptions(o).empty());
  o.window = 1;
  EXPECT_NE(checkDelayTrendOptions(o).find("window"), std::string::npos);
  o = {};
  o.smoothing = 1;
  EXPECT_NE(checkDelayTrendOptions(o).find("smoothing"), std::string::npos);
  EXPECT_STREQ(pathUsageName(PathUsage::kOveruse), "over-use");
}

}  // namespace
}  // namespace telesphere::link
