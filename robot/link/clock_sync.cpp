// SPDX-License-Identifier: MIT
/// @brief ClockSync: minimum-round-trip offset estimation.
#include "robot/link/clock_sync.h"

#include <algorithm>

namespace telesphere::link {

void ClockSync::addSample(std::int64_t client_send_ns, std::int64_t server_ns,
                          std::int64_t client_receive_ns) {
  if (client_receive_ns < client_send_ns) return;
  // (send + receive)/2 without overflow for clocks near INT64_MAX.
  const std::int64_t mid = client_send_ns + (client_receive_ns - client_send_ns) / 2;
  std::lock_guard lock(mutex_);
  samples_.push_back({mid - server_ns, client_receive_ns - client_send_ns});
  if (samples_.size() > kWindow) samples_.pop_front();
}

std::optional<ClockSync::Estimate> ClockSync::estimate() const {
  std::lock_guard lock(mutex_);
  if (samples_.empty()) return std::nullopt;
  return *std::min_element(samples_.begin(), samples_.end(), [](const Estimate& a, const Estimate& b) {
    return a.round_trip_ns < b.round_trip_ns;
  });
}

void ClockSync::reset() {
  std::lock_guard lock(mutex_);
  samples_.clear();
}

std::optional<std::int64_t> ClockSync::serverToClient(std::int64_t server_ns) const {
  const auto e = estimate();
  if (!e) return std::nullopt;
  return server_ns + e->server_to_client_offset_ns;
}

}  // namespace telesphere::link
