// SPDX-License-Identifier: MIT
/// @brief LinkStats: counting and rate-limited logging of drops.
#include "robot/link/link_stats.h"

#include <spdlog/spdlog.h>

namespace telesphere::link {

std::uint64_t LinkStatsSnapshot::droppedTotal() const {
  std::uint64_t total = 0;
  for (auto d : dropped_by_reason) total += d;
  return total;
}

void LinkStats::countDrop(DropReason reason, const char* context) {
  const std::uint64_t n = dropped_[static_cast<int>(reason)].fetch_add(1, std::memory_order_relaxed) + 1;
  // Superseded frames are the normal behaviour of a slow consumer: debug level only.
  if (reason == DropReason::kSuperseded) {
    spdlog::debug("{}: {} message superseded ({} so far)", name_, context, n);
  } else if (reason == DropReason::kRefused) {
    // LinkRefusals says why, once per cause and peer a minute.
  } else if (n == 1 || n % 100 == 0) {
    spdlog::warn("{}: dropped a {} message: {} ({} so far)", name_, context, dropReasonName(reason), n);
  }
}

std::optional<proto::Envelope> LinkStats::parse(const void* data, std::size_t size, const char* context,
                                                std::size_t max_bytes) {
  DropReason why{};
  std::uint32_t peer_version = 0;
  auto envelope = parseEnvelope(data, size, &why, &peer_version, max_bytes);
  if (envelope) return envelope;
  if (why == DropReason::kWrongSchemaVersion &&
      foreign_schema_version_.exchange(peer_version, std::memory_order_relaxed) != peer_version)
    spdlog::warn("{}: a peer speaks link schema v{}, this build speaks v{}: its {} messages are "
                 "dropped (run the same telesphere version on both ends)",
                 name_, peer_version, kSchemaVersion, context);
  countDrop(why, context);
  return std::nullopt;
}

LinkStatsSnapshot LinkStats::snapshot() const {
  LinkStatsSnapshot s;
  s.received = received_.load(std::memory_order_relaxed);
  s.sent = sent_.load(std::memory_order_relaxed);
  for (int i = 0; i < static_cast<int>(DropReason::kCount); ++i)
    s.dropped_by_reason[i] = dropped_[i].load(std::memory_order_relaxed);
  s.foreign_schema_version = foreign_schema_version_.load(std::memory_order_relaxed);
  return s;
}

}  // namespace telesphere::link
