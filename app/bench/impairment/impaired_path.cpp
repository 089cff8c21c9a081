// SPDX-License-Identifier: MIT
#include "app/bench/impairment/impaired_path.h"

#include <algorithm>
#include <cassert>
#include <iterator>
#include <limits>
#include <utility>

namespace telesphere::bench::impairment {

std::string checkPathOptions(const PathOptions& options) {
  if (options.one_way_delay_ns < 0) return "the one-way delay must be ≥ 0";
  if (options.jitter_ns < 0) return "the jitter must be ≥ 0";
  if (options.queue_limit_bytes <= 0) return "the bottleneck queue must hold at least one byte";
  return checkLossOptions(options.loss);
}

ImpairedPath::ImpairedPath(PathOptions options)
    : options_(std::move(options)), loss_(options_.loss), jitter_rng_(options_.jitter_seed) {
  assert(checkPathOptions(options_).empty());
}

std::int64_t ImpairedPath::queuedBytesAt(std::int64_t now_ns) const {
  std::int64_t bytes = 0;
  for (const auto& [leaves_ns, size] : in_bottleneck_)
    if (leaves_ns > now_ns) bytes += size;
  return bytes;
}

OfferResult ImpairedPath::offer(std::vector<std::uint8_t> bytes, std::int64_t now_ns) {
  const auto size = static_cast<std::int64_t>(bytes.size());
  const std::uint64_t index = next_index_++;
  ++stats_.offered;
  stats_.bytes_offered += static_cast<std::uint64_t>(size);
  while (!in_bottleneck_.empty() && in_bottleneck_.front().first <= now_ns) {
    bottleneck_bytes_ -= in_bottleneck_.front().second;
    in_bottleneck_.pop_front();
  }
  if (bottleneck_bytes_ + size > options_.queue_limit_bytes) {
    ++stats_.dropped_queue;
    return OfferResult::kDroppedQueue;
  }
  const std::int64_t start_ns = std::max(now_ns, bottleneck_free_ns_);
  const std::int64_t left_ns = options_.rate.serialisedBy(start_ns, 8.0 * static_cast<double>(size));
  bottleneck_free_ns_ = left_ns;
  in_bottleneck_.emplace_back(left_ns, size);
  bottleneck_bytes_ += size;
  stats_.max_queue_delay_ns = std::max(stats_.max_queue_delay_ns, left_ns - now_ns);
  // Lost on the wire after the bottleneck: it still used the bottleneck's capacity.
  if (loss_.nextLost()) {
    ++stats_.lost;
    return OfferResult::kLost;
  }
  std::int64_t jitter_ns = 0;
  if (options_.jitter_ns > 0) {
    std::uniform_int_distribution<std::int64_t> jitter(-options_.jitter_ns, options_.jitter_ns);
    jitter_ns = jitter(jitter_rng_);
  }
  std::int64_t arrives_ns = left_ns == std::numeric_limits<std::int64_t>::max()
                                ? left_ns
                                : left_ns + std::max<std::int64_t>(0, options_.one_way_delay_ns + jitter_ns);
  if (!options_.reorder) arrives_ns = std::max(arrives_ns, last_arrival_ns_);
  last_arrival_ns_ = std::max(last_arrival_ns_, arrives_ns);
  PathPacket packet{std::move(bytes), now_ns, left_ns, arrives_ns, index};
  const auto at = std::upper_bound(in_flight_.begin(), in_flight_.end(), packet,
                                   [](const PathPacket& a, const PathPacket& b) {
                                     return a.arrives_ns != b.arrives_ns ? a.arrives_ns < b.arrives_ns
                                                                         : a.index < b.index;
                                   });
  in_flight_.insert(at, std::move(packet));
  return OfferResult::kQueued;
}

std::vector<PathPacket> ImpairedPath::arrivedBy(std::int64_t now_ns) {
  std::vector<PathPacket> out;
  auto end = in_flight_.begin();
  while (end != in_flight_.end() && end->arrives_ns <= now_ns) ++end;
  out.assign(std::make_move_iterator(in_flight_.begin()), std::make_move_iterator(end));
  in_flight_.erase(in_flight_.begin(), end);
  for (const PathPacket& packet : out) {
    if (delivered_any_ && packet.index < highest_delivered_index_) ++stats_.reordered;
    highest_delivered_index_ = delivered_any_ ? std::max(highest_delivered_index_, packet.index) : packet.index;
    delivered_any_ = true;
    ++stats_.delivered;
    stats_.bytes_delivered += packet.bytes.size();
  }
  return out;
}

std::optional<std::int64_t> ImpairedPath::nextArrivalNs() const {
  if (in_flight_.empty()) return std::nullopt;
  return in_flight_.front().arrives_ns;
}

}  // namespace telesphere::bench::impairment
