// SPDX-License-Identifier: MIT
/// @brief ClockSync: the sample with the tightest bound (half its round trip plus the drift its
///        age allows) among those of the last kHorizonNs.
#include "robot/link/clock_sync.h"

#include <algorithm>
#include <limits>

namespace telesphere::link {

void ClockSync::addSample(std::int64_t client_send_ns, std::int64_t server_ns,
                          std::int64_t client_receive_ns) {
  if (client_receive_ns < client_send_ns) return;
  // (send + receive)/2 without overflow for clocks near INT64_MAX.
  const std::int64_t mid = client_send_ns + (client_receive_ns - client_send_ns) / 2;
  std::lock_guard lock(mutex_);
  samples_.push_back({mid - server_ns, client_receive_ns - client_send_ns, client_receive_ns});
  // Forget what is beyond the horizon (or from before a clock that stepped back).
  while (samples_.size() > 1 && (client_receive_ns - samples_.front().client_receive_ns > kHorizonNs ||
                                 samples_.front().client_receive_ns > client_receive_ns))
    samples_.pop_front();
  if (samples_.size() > kMaxSamples) samples_.pop_front();

  Estimate e{0, std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::max()};
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const Sample& s = samples_[i];
    const double age_ns = double(client_receive_ns - s.client_receive_ns);
    const double bound_ns = double(s.round_trip_ns) * 0.5 + kDriftBound * age_ns;
    if (bound_ns < double(e.uncertainty_ns)) {
      e.server_to_client_offset_ns = s.offset_ns;
      e.uncertainty_ns = std::int64_t(bound_ns + 0.5);
    }
    if (i + kRecent >= samples_.size()) e.round_trip_ns = std::min(e.round_trip_ns, s.round_trip_ns);
  }
  estimate_ = e;
}

std::optional<ClockSync::Estimate> ClockSync::estimate() const {
  std::lock_guard lock(mutex_);
  return estimate_;
}

void ClockSync::reset() {
  std::lock_guard lock(mutex_);
  samples_.clear();
  estimate_.reset();
}

std::optional<std::int64_t> ClockSync::serverToClient(std::int64_t server_ns) const {
  const auto e = estimate();
  if (!e) return std::nullopt;
  return server_ns + e->server_to_client_offset_ns;
}

}  // namespace telesphere::link
