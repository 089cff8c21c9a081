// SPDX-License-Identifier: MIT
/// @brief Counters of a link endpoint: messages in and out, and every dropped message by reason.
///        Thread-safe; each drop is logged (the first of a reason, then every 100th) with context.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "robot/link/link_schema.h"

namespace telesphere::link {

struct LinkStatsSnapshot {
  std::uint64_t received = 0;
  std::uint64_t sent = 0;
  std::array<std::uint64_t, static_cast<int>(DropReason::kCount)> dropped_by_reason{};
  std::uint64_t dropped(DropReason r) const { return dropped_by_reason[static_cast<int>(r)]; }
  std::uint64_t droppedTotal() const;
  /// The schema version of the last peer that spoke another one (0: none did).
  std::uint32_t foreign_schema_version = 0;
};

class LinkStats {
 public:
  explicit LinkStats(std::string endpoint_name) : name_(std::move(endpoint_name)) {}
  void countReceived() { received_.fetch_add(1, std::memory_order_relaxed); }
  void countSent() { sent_.fetch_add(1, std::memory_order_relaxed); }
  /// Counts a drop and logs it (rate-limited per reason); `context` says where (e.g. "frames").
  void countDrop(DropReason reason, const char* context);
  /// parseEnvelope, with a failure counted as a drop (a foreign schema version remembered and
  /// named in the log). Success is not counted: the caller may still refuse the message.
  std::optional<proto::Envelope> parse(const void* data, std::size_t size, const char* context,
                                       std::size_t max_bytes = kMaxEnvelopeBytes);
  LinkStatsSnapshot snapshot() const;

 private:
  std::string name_;
  std::atomic<std::uint64_t> received_{0};
  std::atomic<std::uint64_t> sent_{0};
  std::array<std::atomic<std::uint64_t>, static_cast<int>(DropReason::kCount)> dropped_{};
  std::atomic<std::uint32_t> foreign_schema_version_{0};
};

}  // namespace telesphere::link
