// SPDX-License-Identifier: MIT
/// @brief SendRateController on simulated paths (app/bench/impairment's ImpairedPath): a paced
///        sender as fast as the target, a receiver reporting every 25 ms over a return path of the
///        same one-way delay. Seeded, on simulated time, so every figure is exact and repeatable:
///        goodput and standing queue at 20, 50 and 100 Mbit/s with 100 ms RTT and 1 % loss; the
///        climb after a step up; the drain after a step down; 2 % loss at 200 ms RTT; a policer
///        (loss, no queue); a sawtooth; the supervisor's cap; a source that sends less than it may.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "app/bench/impairment/impaired_path.h"
#include "robot/link/media/send_rate_controller.h"

namespace telesphere::link::media {
namespace {

using bench::impairment::ImpairedPath;
using bench::impairment::PathOptions;
using bench::impairment::RateTrace;

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kS = 1'000'000'000;
constexpr std::size_t kPacketBytes = 1200;

struct Scenario {
  PathOptions path;
  std::int64_t duration_ns = 20 * kS;
  double source_limit_bps = 0;  ///< 0: the source sends whatever the target allows
  /// A sparse source (a slow encoder): a frame of frame_bytes every frame_period_ns, paced at the
  /// target, nothing between (0: a continuous source).
  std::int64_t frame_period_ns = 0;
  std::size_t frame_bytes = 0;
  double cap_bps = 0;
  std::int64_t feedback_interval_ns = 25 * kMs;
  std::int64_t clock_offset_ns = 123'456'789;  ///< the receiver's clock against the sender's
};

struct Sample {
  std::int64_t t_ns;
  double target_bps, delivered_bps;  ///< delivered: what the path delivered in the last 100 ms
};

struct Outcome {
  std::vector<Sample> samples;                               ///< every 25 ms
  std::vector<std::pair<std::int64_t, std::int64_t>> queue;  ///< (offered ns, queue delay ns) per packet
  SendRateStats stats;
  double max_target_bps = 0;

  double meanDelivered(std::int64_t from_ns, std::int64_t to_ns) const {
    double sum = 0;
    int n = 0;
    for (const Sample& s : samples)
      if (s.t_ns >= from_ns && s.t_ns < to_ns) sum += s.delivered_bps, ++n;
    return n ? sum / n : 0;
  }
  double queueDelayQuantileMs(std::int64_t from_ns, std::int64_t to_ns, double q) const {
    std::vector<std::int64_t> d;
    for (const auto& [t, delay] : queue)
      if (t >= from_ns && t < to_ns) d.push_back(delay);
    if (d.empty()) return 0;
    std::sort(d.begin(), d.end());
    return static_cast<double>(d[static_cast<std::size_t>(q * static_cast<double>(d.size() - 1))]) * 1e-6;
  }
  /// The first sample at or after from_ns where pred holds (and the time), or nothing.
  template <typename P>
  std::optional<std::int64_t> firstAfter(std::int64_t from_ns, P pred) const {
    for (const Sample& s : samples)
      if (s.t_ns >= from_ns && pred(s)) return s.t_ns - from_ns;
    return std::nullopt;
  }
  /// The first time after from_ns from which every packet's queue delay stays below limit.
  std::optional<std::int64_t> queueBelowFrom(std::int64_t from_ns, std::int64_t limit_ns) const {
    std::optional<std::int64_t> last_above;
    for (const auto& [t, delay] : queue)
      if (t >= from_ns && delay >= limit_ns) last_above = t;
    if (!last_above) return 0;
    return *last_above - from_ns;
  }
};

Outcome simulate(const Scenario& sc, SendRateOptions options = {}) {
  ImpairedPath path(sc.path);
  SendRateController controller(options);
  if (sc.cap_bps > 0) controller.setCapBps(sc.cap_bps);
  Outcome out;
  std::uint32_t seq = 0;
  std::int64_t next_send = 0, next_feedback = sc.feedback_interval_ns;
  struct InReturn {
    std::int64_t arrives_ns;
    std::vector<PacketReport> reports;
    std::int64_t hold_ns;  ///< the newest entry's wait at the receiver (-1: no entries)
  };
  std::vector<InReturn> in_return;
  std::vector<std::pair<std::int64_t, std::size_t>> delivered_log;            ///< (arrival ns, bytes)
  const std::int64_t back_delay = sc.path.one_way_delay_ns;
  while (true) {
    const std::int64_t t = std::min(next_send, next_feedback);
    if (t >= sc.duration_ns) break;
    if (t == next_send) {
      std::vector<std::uint8_t> bytes(kPacketBytes);
      std::memcpy(bytes.data(), &seq, sizeof seq);
      controller.onPacketSent(seq, t, kPacketBytes);
      path.offer(std::move(bytes), t);
      ++seq;
      double rate = controller.targetBps();
      if (sc.source_limit_bps > 0) rate = std::min(rate, sc.source_limit_bps);
      next_send = t + static_cast<std::int64_t>(8.0 * kPacketBytes * 1e9 / rate);
      if (sc.frame_period_ns > 0 && seq % (sc.frame_bytes / kPacketBytes) == 0)  // the frame is out
        next_send = std::max(next_send, (t / sc.frame_period_ns + 1) * sc.frame_period_ns);
    } else {
      // The receiver reports what arrived since its last report.
      std::vector<PacketReport> reports;
      std::int64_t newest_arrival_ns = -1;
      for (const auto& p : path.arrivedBy(t)) {
        newest_arrival_ns = p.arrives_ns;
        std::uint32_t s = 0;
        std::memcpy(&s, p.bytes.data(), sizeof s);
        reports.push_back({s, p.arrives_ns + sc.clock_offset_ns});
        delivered_log.emplace_back(p.arrives_ns, p.bytes.size());
        out.queue.emplace_back(p.offered_ns, p.left_bottleneck_ns - p.offered_ns);
      }
      const std::int64_t hold_ns = newest_arrival_ns < 0 ? -1 : t - newest_arrival_ns;
      in_return.push_back({t + back_delay, std::move(reports), hold_ns});
      next_feedback = t + sc.feedback_interval_ns;
      // Reports that reached the sender by now.
      while (!in_return.empty() && in_return.front().arrives_ns <= t) {
        controller.onFeedback(in_return.front().reports, t, in_return.front().hold_ns);
        in_return.erase(in_return.begin());
      }
      double bytes = 0;
      for (auto it = delivered_log.rbegin(); it != delivered_log.rend() && it->first > t - 100 * kMs; ++it)
        bytes += static_cast<double>(it->second);
      out.samples.push_back({t, controller.targetBps(), 8.0 * bytes / 0.1});
      out.max_target_bps = std::max(out.max_target_bps, controller.targetBps());
    }
  }
  out.stats = controller.stats();
  if (std::getenv("TELESPHERE_RATE_TRACE"))
    for (const Sample& s : out.samples)
      if (s.t_ns % (250 * kMs) == 0)
        std::printf("  t %6.2f s  target %7.2f  delivered %7.2f Mbit/s\n", static_cast<double>(s.t_ns) * 1e-9,
                    s.target_bps * 1e-6, s.delivered_bps * 1e-6);
  return out;
}

PathOptions internetPath(double rate_bps, std::int64_t rtt_ns, double loss, std::uint64_t seed = 3) {
  PathOptions p;
  p.one_way_delay_ns = rtt_ns / 2;
  p.jitter_ns = 5 * kMs;  // ± 5 ms each way: ± 10 ms on the round trip
  p.loss.loss_fraction = loss;
  p.loss.seed = seed;
  p.rate = RateTrace::constant(rate_bps);
  p.queue_limit_bytes = 1 << 20;
  return p;
}

RateTrace stepTrace(double start, std::int64_t at_ns, double then) {
  std::string error;
  auto trace = RateTrace::steps(start, {{at_ns, then}}, &error);
  EXPECT_TRUE(trace) << error;
  return *trace;
}

TEST(SendRateController, UsesTheLinkWithoutAStandingQueueAt100msRttAnd1PercentLoss) {
  for (double mbit : {20.0, 50.0, 100.0}) {
    Scenario sc;
    sc.path = internetPath(mbit * 1e6, 100 * kMs, 0.01);
    const Outcome o = simulate(sc);
    const double goodput = o.meanDelivered(8 * kS, 20 * kS) / (mbit * 1e6);
    const double q95 = o.queueDelayQuantileMs(8 * kS, 20 * kS, 0.95);
    std::printf("%5.0f Mbit/s: goodput %.3f, queue p95 %.1f ms, decisions: overuse %llu, loss %llu, lost %llu\n", mbit,
                goodput, q95, static_cast<unsigned long long>(o.stats.decided(RateDecision::kDecreaseOveruse)),
                static_cast<unsigned long long>(o.stats.decided(RateDecision::kDecreaseLoss)),
                static_cast<unsigned long long>(o.stats.packets_lost));
    EXPECT_GE(goodput, 0.85) << mbit << " Mbit/s";
    EXPECT_LE(q95, 30.0) << mbit << " Mbit/s";
    EXPECT_EQ(o.stats.decided(RateDecision::kDecreaseLoss), 0u) << "1 % loss is the path's, not congestion";
    // The round trip from the reports' holds: the path's 100 ms plus what queues on it.
    EXPECT_GE(o.stats.rtt_ms, 100.0) << mbit << " Mbit/s";
    EXPECT_LE(o.stats.rtt_ms, 100.0 + 30.0) << mbit << " Mbit/s";
  }
}

TEST(SendRateController, ClimbsFrom20To80MbitWithinThreeSecondsOfAStepUp) {
  Scenario sc;
  sc.path = internetPath(20e6, 100 * kMs, 0.01);
  sc.path.rate = stepTrace(20e6, 10 * kS, 100e6);
  const Outcome o = simulate(sc);
  const auto climb = o.firstAfter(10 * kS, [](const Sample& s) { return s.delivered_bps >= 80e6; });
  ASSERT_TRUE(climb);
  std::printf("20 -> 100 Mbit/s: 80 Mbit/s delivered after %.2f s\n", static_cast<double>(*climb) * 1e-9);
  EXPECT_LE(*climb, 3 * kS);
}

TEST(SendRateController, DrainsTheQueueQuicklyAfterAStepDown) {
  Scenario sc;
  sc.path = internetPath(100e6, 100 * kMs, 0.01);
  sc.path.rate = stepTrace(100e6, 10 * kS, 20e6);
  const Outcome o = simulate(sc);
  const auto drained = o.queueBelowFrom(10 * kS, 100 * kMs);
  ASSERT_TRUE(drained);
  const double worst = o.queueDelayQuantileMs(10 * kS, 20 * kS, 1.0);
  std::printf("100 -> 20 Mbit/s: queue below 100 ms for good %.2f s after the step, worst %.0f ms; goodput after %.3f\n",
              static_cast<double>(*drained) * 1e-9, worst, o.meanDelivered(13 * kS, 20 * kS) / 20e6);
  EXPECT_LE(*drained, 1 * kS);
  EXPECT_GE(o.meanDelivered(13 * kS, 20 * kS) / 20e6, 0.85);
}

TEST(SendRateController, StaysUsefulAt200msRttAnd2PercentLossAndInBursts) {
  for (double burst : {1.0, 4.0}) {
    Scenario sc;
    sc.path = internetPath(50e6, 200 * kMs, 0.02);
    sc.path.loss.mean_burst_packets = burst;
    const Outcome o = simulate(sc);
    const double goodput = o.meanDelivered(10 * kS, 20 * kS) / 50e6;
    std::printf("200 ms RTT, 2 %% loss in bursts of %.0f: goodput %.3f, queue p95 %.1f ms\n", burst, goodput,
                o.queueDelayQuantileMs(10 * kS, 20 * kS, 0.95));
    EXPECT_GE(goodput, 0.8) << "bursts of " << burst;
    EXPECT_EQ(o.stats.decided(RateDecision::kDecreaseLoss), 0u);
  }
}

TEST(SendRateController, BacksOffAPolicerThatDropsWithoutQueuing) {
  // A token bucket with almost no buffer: exceeding it costs loss, not delay.
  Scenario sc;
  sc.path = internetPath(20e6, 100 * kMs, 0.0);
  sc.path.queue_limit_bytes = 3 * static_cast<std::int64_t>(kPacketBytes);
  const Outcome o = simulate(sc);
  const double goodput = o.meanDelivered(8 * kS, 20 * kS) / 20e6;
  std::printf("policer at 20 Mbit/s: goodput %.3f, loss decreases %llu, max target %.1f Mbit/s\n", goodput,
              static_cast<unsigned long long>(o.stats.decided(RateDecision::kDecreaseLoss)), o.max_target_bps * 1e-6);
  EXPECT_GT(o.stats.decided(RateDecision::kDecreaseLoss) + o.stats.decided(RateDecision::kDecreaseOveruse), 0u);
  EXPECT_GE(goodput, 0.6);
  EXPECT_LT(o.samples.back().target_bps, 2 * 20e6) << "the target must not run away from a lossy bottleneck";
}

TEST(SendRateController, FollowsASawtooth) {
  Scenario sc;
  sc.path = internetPath(20e6, 100 * kMs, 0.01);
  sc.path.rate = RateTrace::sawtooth(20e6, 60e6, 8 * kS, 100 * kMs, 40 * kS);
  sc.duration_ns = 40 * kS;
  const Outcome o = simulate(sc);
  double capacity = 0;
  int n = 0;
  for (const Sample& s : o.samples)
    if (s.t_ns >= 8 * kS) capacity += sc.path.rate.bitsPerSecondAt(s.t_ns), ++n;
  const double goodput = o.meanDelivered(8 * kS, 40 * kS) / (capacity / n);
  std::printf("sawtooth 20..60 Mbit/s over 8 s: goodput %.3f, queue p95 %.1f ms\n", goodput,
              o.queueDelayQuantileMs(8 * kS, 40 * kS, 0.95));
  EXPECT_GE(goodput, 0.7);
  EXPECT_LE(o.queueDelayQuantileMs(8 * kS, 40 * kS, 0.95), 200.0) << "a threefold drop every 8 s";
}

TEST(SendRateController, KeepsToTheSupervisorsCapAndToWhatTheSourceSends) {
  Scenario capped;
  capped.path = internetPath(100e6, 50 * kMs, 0.0);
  capped.cap_bps = 5e6;
  const Outcome c = simulate(capped);
  EXPECT_LE(c.max_target_bps, 5e6);
  EXPECT_GT(c.stats.decided(RateDecision::kLimitedByCap), 0u);
  EXPECT_GE(c.meanDelivered(5 * kS, 20 * kS), 0.95 * 5e6);

  Scenario limited;
  limited.path = internetPath(100e6, 50 * kMs, 0.0);
  limited.source_limit_bps = 12e6;
  const Outcome l = simulate(limited);
  // 1.5 × what arrived + 1 Mbit/s, the arrival rate measured over 300 ms of ±5 ms jitter (±4 %).
  EXPECT_LE(l.samples.back().target_bps, 1.5 * 12e6 * 1.04 + 1e6);
  EXPECT_GT(l.stats.decided(RateDecision::kLimitedByDelivery), 0u);
}

// A source slower than the delivered rate's window (HEVC at 3 Hz on a slow CPU: a frame every
// 330 ms) leaves windows with nothing delivered. Nothing delivered is no evidence that the path
// carries more: the target must not grow then (it ran to the 1 Gbit/s maximum, and paced at that
// every frame left as one burst into the bottleneck).
TEST(SendRateController, ASparseSourceDoesNotPushTheTargetToTheSky) {
  Scenario sparse;
  sparse.path = internetPath(20e6, 100 * kMs, 0.01);
  sparse.frame_period_ns = 400 * kMs;
  sparse.frame_bytes = 84 * kPacketBytes;  // about 100 kB a frame: 2 Mbit/s
  const Outcome o = simulate(sparse);
  std::printf("sparse source (2 Mbit/s in frames every 400 ms): target max %.1f Mbit/s, at the end %.1f\n",
              o.max_target_bps * 1e-6, o.samples.back().target_bps * 1e-6);
  EXPECT_LE(o.max_target_bps, 20e6) << "above what the source could ever show the path carries";
}

TEST(SendRateController, RefusesOptionsThatCannotWork) {
  SendRateOptions o;
  o.min_bps = 0;
  EXPECT_THROW(SendRateController{o}, std::invalid_argument);
  o = {};
  o.backoff = 1.0;
  EXPECT_NE(checkSendRateOptions(o), "");
  o = {};
  o.growth_far_per_s = 0.5;
  EXPECT_NE(checkSendRateOptions(o), "");
  EXPECT_EQ(checkSendRateOptions({}), "");
}

TEST(SendRateController, TheRoundTripIsTheNewestReportsAgeLessItsHold) {
  SendRateController c;
  EXPECT_LT(c.stats().rtt_ms, 0.0) << "nothing measured yet";
  c.onPacketSent(0, 0, 1200);
  c.onPacketSent(1, 1 * kMs, 1200);
  // The receiver's clock is its own (40 ms here); only the hold and the sender's clock count.
  const PacketReport first[] = {{0, 40 * kMs}, {1, 41 * kMs}};
  c.onFeedback(first, 100 * kMs, 9 * kMs);  // seq 1: sent at 1 ms, held 9 ms, here at 100 ms
  EXPECT_DOUBLE_EQ(c.stats().rtt_last_ms, 90.0);
  EXPECT_DOUBLE_EQ(c.stats().rtt_ms, 90.0);
  c.onPacketSent(2, 100 * kMs, 1200);
  const PacketReport second[] = {{2, 160 * kMs}};
  c.onFeedback(second, 230 * kMs, 10 * kMs);  // 120 ms: the smoothed value moves an eighth of the way
  EXPECT_DOUBLE_EQ(c.stats().rtt_last_ms, 120.0);
  EXPECT_DOUBLE_EQ(c.stats().rtt_ms, 90.0 + 30.0 / 8.0);
  // No hold (an old receiver), a hold longer than the round trip, the newest entry unknown: no sample.
  c.onPacketSent(3, 230 * kMs, 1200);
  c.onPacketSent(4, 231 * kMs, 1200);
  c.onPacketSent(5, 232 * kMs, 1200);
  const PacketReport third[] = {{3, 300 * kMs}};
  c.onFeedback(third, 330 * kMs);
  const PacketReport fourth[] = {{4, 301 * kMs}};
  c.onFeedback(fourth, 331 * kMs, 200 * kMs);
  const PacketReport fifth[] = {{5, 302 * kMs}, {77, 303 * kMs}};
  c.onFeedback(fifth, 332 * kMs, 1 * kMs);
  EXPECT_DOUBLE_EQ(c.stats().rtt_last_ms, 120.0);
  EXPECT_DOUBLE_EQ(c.stats().rtt_ms, 90.0 + 30.0 / 8.0);
}

TEST(SendRateController, IgnoresReportsOfPacketsItNeverSent) {
  SendRateController c;
  c.onPacketSent(10, 0, 1200);
  c.onPacketSent(11, 1 * kMs, 1200);
  const PacketReport reports[] = {{11, 50 * kMs}, {11, 51 * kMs}, {99, 52 * kMs}, {9, 53 * kMs}};
  c.onFeedback(reports, 60 * kMs);
  EXPECT_EQ(c.stats().packets_reported, 1u);
  EXPECT_EQ(c.stats().reports_unknown, 3u);
  EXPECT_EQ(c.stats().packets_lost, 0u) << "seq 10 was sent 1 ms before 11: within the reorder window";
}

}  // namespace
}  // namespace telesphere::link::media
