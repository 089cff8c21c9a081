// SPDX-License-Identifier: MIT
/// @brief Clock offset and round trip between a link client and the server from ping exchanges,
///        so latencies measured across two machines are right without NTP (DESIGN.md §1).
///
/// A sample is (client_send_ns, server_ns, client_receive_ns). Assuming the two legs take equally
/// long, server_to_client_offset_ns = (client_send_ns + client_receive_ns)/2 − server_ns, i.e.
/// t_client ≈ t_server + server_to_client_offset_ns, wrong by at most half the round trip. The
/// estimate uses the sample with the smallest round trip among the last kWindow samples (its
/// error bound is the tightest; queueing only ever lengthens a round trip).
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace telesphere::link {

class ClockSync {
 public:
  static constexpr std::size_t kWindow = 32;

  struct Estimate {
    std::int64_t server_to_client_offset_ns;  ///< t_client ≈ t_server + offset
    std::int64_t round_trip_ns;               ///< of the sample used; the offset is good to ±half
  };

  /// Adds one ping exchange; ignores samples whose receive precedes their send.
  void addSample(std::int64_t client_send_ns, std::int64_t server_ns, std::int64_t client_receive_ns);
  std::optional<Estimate> estimate() const;
  /// Forgets every sample (the server restarted: its clock may be another machine's).
  void reset();
  /// Server time converted to the client clock (nothing before the first sample).
  std::optional<std::int64_t> serverToClient(std::int64_t server_ns) const;

 private:
  mutable std::mutex mutex_;
  std::deque<Estimate> samples_;
};

}  // namespace telesphere::link
