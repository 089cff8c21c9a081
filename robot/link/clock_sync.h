// SPDX-License-Identifier: MIT
/// @brief Clock offset and round trip between a link client and the server from ping exchanges,
///        so latencies measured across two machines are right without NTP (DESIGN.md §1).
///
/// A sample is (client_send_ns, server_ns, client_receive_ns). Assuming the two legs take equally
/// long, server_to_client_offset_ns = (client_send_ns + client_receive_ns)/2 − server_ns, i.e.
/// t_client ≈ t_server + server_to_client_offset_ns, wrong by at most half the round trip: a
/// queue on one leg only (an Internet downlink a bulk flow fills) moves it by half that queue.
/// So the estimate keeps the samples of the last kHorizonNs and uses the one with the tightest
/// bound: half its round trip plus what the clocks may have drifted since (kDriftBound × its
/// age). Queueing only ever lengthens a round trip, so a sample from before a queue stood keeps
/// the offset right while it stands (up to about kHorizonNs; beyond that the queue is the path),
/// and clocks that drift apart are followed within about a minute.
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace telesphere::link {

class ClockSync {
 public:
  /// Exchanges whose smallest round trip is the path's round trip now.
  static constexpr std::size_t kRecent = 32;
  /// Samples older than this (client clock) are forgotten.
  static constexpr std::int64_t kHorizonNs = 600'000'000'000;
  /// At most this many samples are kept (a ping every 73 ms fills the horizon).
  static constexpr std::size_t kMaxSamples = 8192;
  /// How fast two clocks may drift apart: two crystals at ±50 ppm.
  static constexpr double kDriftBound = 100e-6;

  struct Estimate {
    std::int64_t server_to_client_offset_ns;  ///< t_client ≈ t_server + offset
    /// The offset is good to ± this: half the round trip of the sample used, plus kDriftBound × its age.
    std::int64_t uncertainty_ns;
    /// The path's round trip now: the smallest of the last kRecent exchanges.
    std::int64_t round_trip_ns;
  };

  /// Adds one ping exchange; ignores samples whose receive precedes their send.
  void addSample(std::int64_t client_send_ns, std::int64_t server_ns, std::int64_t client_receive_ns);
  std::optional<Estimate> estimate() const;
  /// Forgets every sample (the server restarted: its clock may be another machine's).
  void reset();
  /// Server time converted to the client clock (nothing before the first sample).
  std::optional<std::int64_t> serverToClient(std::int64_t server_ns) const;

 private:
  struct Sample {
    std::int64_t offset_ns, round_trip_ns, client_receive_ns;
  };
  mutable std::mutex mutex_;
  std::deque<Sample> samples_;  ///< oldest first, within kHorizonNs of the newest
  std::optional<Estimate> estimate_;
};

}  // namespace telesphere::link
