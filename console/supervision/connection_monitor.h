// SPDX-License-Identifier: MIT
/// @brief Whether the robot and the XR app are there, from when the console last heard them
///        (DESIGN.md §1; issue: connected / silent / gone, with how long). Qt-free; time is
///        passed in (steady ns), so tests drive it without sleeping.
///
/// A peer is `waiting` until first heard, `connected` while heard within silent_after, `silent`
/// until gone_after, then `gone`. For each state the monitor keeps when it began, so the
/// console says "connected for 2 min", "silent for 3.1 s", "waiting for 12 s".
#pragma once

#include <cstdint>
#include <string>

namespace telesphere::console::supervision {

enum class PeerState { kWaiting, kConnected, kSilent, kGone };

const char* peerStateName(PeerState state);  ///< "waiting", "connected", "silent", "gone"

struct PeerThresholds {
  std::int64_t silent_after_ns = 1'000'000'000;
  std::int64_t gone_after_ns = 5'000'000'000;
};

class PeerMonitor {
 public:
  PeerMonitor(std::int64_t start_ns, PeerThresholds thresholds)
      : thresholds_(thresholds), since_ns_(start_ns) {}

  /// Updates from `last_heard_ns` (0: never) as of now_ns; returns the state.
  PeerState update(std::int64_t last_heard_ns, std::int64_t now_ns);

  PeerState state() const { return state_; }
  /// Seconds in the current state as of the last update.
  double seconds() const { return double(now_ns_ - since_ns_) * 1e-9; }
  /// How often the peer went from silent or gone back to connected.
  int reconnects() const { return reconnects_; }
  /// "connected for 12.0 s", "gone for 3 min", …
  std::string describe() const;

 private:
  PeerThresholds thresholds_;
  PeerState state_ = PeerState::kWaiting;
  std::int64_t since_ns_;
  std::int64_t now_ns_ = 0;
  int reconnects_ = 0;
};

/// "4.2 s", "3 min 05 s", "2 h 10 min": a duration for a status line.
std::string formatDuration(double seconds);

}  // namespace telesphere::console::supervision
