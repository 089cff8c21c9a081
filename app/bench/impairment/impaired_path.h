// SPDX-License-Identifier: MIT
/// @brief One direction of an impaired network path, on a clock the caller drives (simulated time
///        in tests, the steady clock in a relay): a bottleneck of a given rate (RateTrace) with a
///        finite drop-tail queue, then random or burst loss (LossModel), then a one-way delay with
///        jitter, packets reordered by their jitter or kept in order. All times in ns.
///
///        A packet offered at t joins the queue if the bytes still waiting or in service there
///        plus its own fit in `queue_limit_bytes` (else dropped, "queue"); it starts serialising
///        when the one before it has left, leaves the bottleneck at RateTrace::serialisedBy, is
///        then lost with the loss model ("loss"), and arrives one_way_delay_ns + jitter later,
///        jitter uniform in [−jitter_ns, +jitter_ns] (never before it left). Without reordering,
///        a packet never arrives before the one offered before it.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "app/bench/impairment/loss_model.h"
#include "app/bench/impairment/rate_trace.h"

namespace telesphere::bench::impairment {

struct PathOptions {
  std::int64_t one_way_delay_ns = 0;
  std::int64_t jitter_ns = 0;  ///< ± around the delay, uniform
  bool reorder = false;        ///< let jitter reorder packets (else arrivals keep the offer order)
  LossOptions loss;
  RateTrace rate;                                        ///< no limit by default
  std::int64_t queue_limit_bytes = 1 << 20;              ///< the bottleneck's buffer (drop-tail)
  std::uint64_t jitter_seed = 2;
};

/// Nothing wrong: empty; else what is wrong.
std::string checkPathOptions(const PathOptions& options);

struct PathPacket {
  std::vector<std::uint8_t> bytes;
  std::int64_t offered_ns = 0;
  std::int64_t left_bottleneck_ns = 0;
  std::int64_t arrives_ns = 0;
  std::uint64_t index = 0;  ///< offer order, from 0
};

struct PathStats {
  std::uint64_t offered = 0, delivered = 0, dropped_queue = 0, lost = 0;
  std::uint64_t bytes_offered = 0, bytes_delivered = 0;
  std::uint64_t reordered = 0;      ///< delivered before a packet offered earlier
  std::int64_t max_queue_delay_ns = 0;  ///< offer to leaving the bottleneck, worst so far
};

enum class OfferResult { kQueued, kDroppedQueue, kLost };

class ImpairedPath {
 public:
  /// Options must pass checkPathOptions (asserted in debug builds).
  explicit ImpairedPath(PathOptions options);

  /// A packet enters the path at now_ns (never earlier than the previous offer's now_ns).
  OfferResult offer(std::vector<std::uint8_t> bytes, std::int64_t now_ns);
  /// The packets that have arrived by now_ns, in arrival order (ties in offer order).
  std::vector<PathPacket> arrivedBy(std::int64_t now_ns);
  /// When the next packet arrives; nothing while the path is empty.
  std::optional<std::int64_t> nextArrivalNs() const;
  /// Bytes waiting or in service at the bottleneck at now_ns.
  std::int64_t queuedBytesAt(std::int64_t now_ns) const;

  const PathStats& stats() const { return stats_; }

 private:
  PathOptions options_;
  LossModel loss_;
  std::mt19937_64 jitter_rng_;
  std::int64_t bottleneck_free_ns_ = 0;  ///< when the last accepted packet leaves the bottleneck
  std::deque<std::pair<std::int64_t, std::int64_t>> in_bottleneck_;  ///< (leaves_ns, bytes)
  std::int64_t bottleneck_bytes_ = 0;  ///< the sum of in_bottleneck_'s bytes (offer runs per packet)
  std::vector<PathPacket> in_flight_;    ///< sorted by (arrives_ns, index)
  std::int64_t last_arrival_ns_ = 0;
  std::uint64_t next_index_ = 0;
  std::uint64_t highest_delivered_index_ = 0;
  bool delivered_any_ = false;
  PathStats stats_;
};

}  // namespace telesphere::bench::impairment
