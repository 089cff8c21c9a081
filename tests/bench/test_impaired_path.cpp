// SPDX-License-Identifier: MIT
/// @brief ImpairedPath on simulated time: exact departure and arrival times behind a rate limit,
///        drop-tail at the queue limit, delay and jitter with and without reordering, loss counted.
#include <gtest/gtest.h>

#include <algorithm>

#include "app/bench/impairment/impaired_path.h"

namespace telesphere::bench::impairment {
namespace {

constexpr std::int64_t kMs = 1'000'000;

std::vector<std::uint8_t> bytes(std::size_t n) { return std::vector<std::uint8_t>(n, 0xab); }

TEST(ImpairedPath, ABottleneckSpacesPacketsAndDelayShiftsThem) {
  PathOptions options;
  options.rate = RateTrace::constant(1e6);  // 1250 bytes = 10 ms
  options.one_way_delay_ns = 50 * kMs;
  ImpairedPath path(options);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(path.offer(bytes(1250), 0), OfferResult::kQueued);
  EXPECT_EQ(path.queuedBytesAt(0), 5 * 1250);
  EXPECT_EQ(path.queuedBytesAt(25 * kMs), 3 * 1250);
  EXPECT_EQ(path.nextArrivalNs(), 60 * kMs);
  EXPECT_TRUE(path.arrivedBy(60 * kMs - 1).empty());
  const auto arrived = path.arrivedBy(1000 * kMs);
  ASSERT_EQ(arrived.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(arrived[i].left_bottleneck_ns, static_cast<std::int64_t>(i + 1) * 10 * kMs);
    EXPECT_EQ(arrived[i].arrives_ns, static_cast<std::int64_t>(i + 1) * 10 * kMs + 50 * kMs);
    EXPECT_EQ(arrived[i].index, i);
    EXPECT_EQ(arrived[i].bytes.size(), 1250u);
  }
  EXPECT_EQ(path.stats().max_queue_delay_ns, 50 * kMs);
  EXPECT_EQ(path.stats().delivered, 5u);
  EXPECT_EQ(path.stats().bytes_delivered, 5u * 1250);
  EXPECT_FALSE(path.nextArrivalNs());
}

TEST(ImpairedPath, TheQueueDropsTheTailAtItsLimit) {
  PathOptions options;
  options.rate = RateTrace::constant(1e6);
  options.queue_limit_bytes = 3000;
  ImpairedPath path(options);
  EXPECT_EQ(path.offer(bytes(1250), 0), OfferResult::kQueued);
  EXPECT_EQ(path.offer(bytes(1250), 0), OfferResult::kQueued);
  EXPECT_EQ(path.offer(bytes(1250), 0), OfferResult::kDroppedQueue);
  // After the first has left (10 ms), there is room again.
  EXPECT_EQ(path.offer(bytes(1250), 10 * kMs), OfferResult::kQueued);
  // A packet larger than the whole queue never fits.
  EXPECT_EQ(path.offer(bytes(3001), 1000 * kMs), OfferResult::kDroppedQueue);
  EXPECT_EQ(path.stats().dropped_queue, 2u);
  EXPECT_EQ(path.stats().offered, 5u);
  const auto arrived = path.arrivedBy(1000 * kMs);
  ASSERT_EQ(arrived.size(), 3u);
  EXPECT_EQ(arrived[2].left_bottleneck_ns, 30 * kMs);  // behind the second, which left at 20 ms
}

TEST(ImpairedPath, AStepDownDrainsTheQueueAtTheNewRate) {
  std::string error;
  PathOptions options;
  options.rate = *RateTrace::steps(2e6, {{10 * kMs, 1e6}}, &error);
  ImpairedPath path(options);
  for (int i = 0; i < 4; ++i) path.offer(bytes(1250), 0);  // 5 ms each at 2 Mbit/s, 10 ms at 1
  const auto arrived = path.arrivedBy(1000 * kMs);
  ASSERT_EQ(arrived.size(), 4u);
  EXPECT_EQ(arrived[0].left_bottleneck_ns, 5 * kMs);
  EXPECT_EQ(arrived[1].left_bottleneck_ns, 10 * kMs);
  EXPECT_EQ(arrived[2].left_bottleneck_ns, 20 * kMs);
  EXPECT_EQ(arrived[3].left_bottleneck_ns, 30 * kMs);
}

TEST(ImpairedPath, JitterWithoutReorderingKeepsTheOrder) {
  PathOptions options;
  options.one_way_delay_ns = 100 * kMs;
  options.jitter_ns = 10 * kMs;
  ImpairedPath path(options);
  for (int i = 0; i < 2000; ++i) path.offer(bytes(100), i * kMs);  // 1 ms apart, jitter ± 10 ms
  const auto arrived = path.arrivedBy(10'000 * kMs);
  ASSERT_EQ(arrived.size(), 2000u);
  for (std::size_t i = 0; i < arrived.size(); ++i) {
    EXPECT_EQ(arrived[i].index, i);
    const std::int64_t delay = arrived[i].arrives_ns - arrived[i].offered_ns;
    EXPECT_GE(delay, 90 * kMs);
    EXPECT_LE(delay, 110 * kMs + 20 * kMs);  // held behind an earlier, later-jittered packet
  }
  EXPECT_EQ(path.stats().reordered, 0u);
}

TEST(ImpairedPath, JitterWithReorderingReordersAndStaysInItsBand) {
  PathOptions options;
  options.one_way_delay_ns = 100 * kMs;
  options.jitter_ns = 10 * kMs;
  options.reorder = true;
  ImpairedPath path(options);
  for (int i = 0; i < 2000; ++i) path.offer(bytes(100), i * kMs);
  const auto arrived = path.arrivedBy(10'000 * kMs);
  ASSERT_EQ(arrived.size(), 2000u);
  std::int64_t min_delay = INT64_MAX, max_delay = 0;
  for (const PathPacket& p : arrived) {
    min_delay = std::min(min_delay, p.arrives_ns - p.offered_ns);
    max_delay = std::max(max_delay, p.arrives_ns - p.offered_ns);
  }
  EXPECT_GE(min_delay, 90 * kMs);
  EXPECT_LE(max_delay, 110 * kMs);
  EXPECT_GT(max_delay - min_delay, 18 * kMs);  // the band is used
  EXPECT_GT(path.stats().reordered, 100u);
  EXPECT_TRUE(std::is_sorted(arrived.begin(), arrived.end(),
                             [](const PathPacket& a, const PathPacket& b) { return a.arrives_ns < b.arrives_ns; }));
}

TEST(ImpairedPath, LostPacketsStillUsedTheBottleneck) {
  PathOptions options;
  options.rate = RateTrace::constant(8e6);  // 1000 bytes = 1 ms
  options.loss = {0.2, 1, 5};
  ImpairedPath path(options);
  int lost = 0;
  for (int i = 0; i < 1000; ++i) lost += path.offer(bytes(1000), 0) == OfferResult::kLost;
  const auto arrived = path.arrivedBy(INT64_MAX - 1);
  EXPECT_EQ(static_cast<int>(path.stats().lost), lost);
  EXPECT_EQ(arrived.size() + static_cast<std::size_t>(lost), 1000u);
  EXPECT_NEAR(lost / 1000.0, 0.2, 0.05);
  // The last packet offered left after 1000 ms whether or not the ones before it were lost.
  const std::int64_t last_left = std::max_element(arrived.begin(), arrived.end(), [](auto& a, auto& b) {
                                   return a.index < b.index;
                                 })->left_bottleneck_ns;
  EXPECT_LE(last_left, 1000 * kMs);
  EXPECT_GE(last_left, 990 * kMs);
}

TEST(ImpairedPath, TheSameSeedsGiveTheSameRun) {
  auto run = [](std::uint64_t seed) {
    PathOptions options;
    options.one_way_delay_ns = 30 * kMs;
    options.jitter_ns = 5 * kMs;
    options.reorder = true;
    options.loss = {0.05, 3, seed};
    options.jitter_seed = seed + 100;
    ImpairedPath path(options);
    for (int i = 0; i < 500; ++i) path.offer(bytes(10), i * kMs / 2);
    std::vector<std::pair<std::uint64_t, std::int64_t>> out;
    for (const auto& p : path.arrivedBy(INT64_MAX - 1)) out.emplace_back(p.index, p.arrives_ns);
    return out;
  };
  EXPECT_EQ(run(1), run(1));
  EXPECT_NE(run(1), run(2));
}

TEST(ImpairedPath, ExtremesAreNamedOrHandled) {
  PathOptions bad;
  bad.one_way_delay_ns = -1;
  EXPECT_NE(checkPathOptions(bad).find("delay"), std::string::npos);
  bad = {};
  bad.jitter_ns = -1;
  EXPECT_NE(checkPathOptions(bad).find("jitter"), std::string::npos);
  bad = {};
  bad.queue_limit_bytes = 0;
  EXPECT_NE(checkPathOptions(bad).find("queue"), std::string::npos);
  // Jitter larger than the delay: never earlier than leaving the bottleneck.
  PathOptions wild;
  wild.one_way_delay_ns = 1 * kMs;
  wild.jitter_ns = 50 * kMs;
  wild.reorder = true;
  ImpairedPath path(wild);
  for (int i = 0; i < 200; ++i) path.offer(bytes(1), 10 * kMs);
  for (const auto& p : path.arrivedBy(INT64_MAX - 1)) EXPECT_GE(p.arrives_ns, 10 * kMs);
  // An empty datagram takes no time at any rate.
  PathOptions slow;
  slow.rate = RateTrace::constant(1);
  ImpairedPath empty(slow);
  empty.offer({}, 5);
  EXPECT_EQ(empty.nextArrivalNs(), 5);
}

}  // namespace
}  // namespace telesphere::bench::impairment
