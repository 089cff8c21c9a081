// SPDX-License-Identifier: MIT
/// @brief PeerMonitor: a four-state timer.
#include "console/supervision/connection_monitor.h"

#include <cmath>
#include <cstdio>

namespace telesphere::console::supervision {

const char* peerStateName(PeerState state) {
  switch (state) {
    case PeerState::kWaiting: return "waiting";
    case PeerState::kConnected: return "connected";
    case PeerState::kSilent: return "silent";
    case PeerState::kGone: return "gone";
  }
  return "?";
}

PeerState PeerMonitor::update(std::int64_t last_heard_ns, std::int64_t now_ns) {
  now_ns_ = now_ns;
  PeerState next = state_;
  if (last_heard_ns == 0) {
    next = state_ == PeerState::kWaiting ? PeerState::kWaiting : PeerState::kGone;
  } else {
    const std::int64_t quiet = now_ns - last_heard_ns;
    next = quiet < thresholds_.silent_after_ns ? PeerState::kConnected
           : quiet < thresholds_.gone_after_ns ? PeerState::kSilent
                                               : PeerState::kGone;
    if (state_ == PeerState::kWaiting && next != PeerState::kConnected) next = PeerState::kWaiting;
  }
  if (next != state_) {
    if (next == PeerState::kConnected && (state_ == PeerState::kSilent || state_ == PeerState::kGone))
      ++reconnects_;
    // Silent and gone count from the last time the peer was heard, not from when we noticed.
    since_ns_ = (next == PeerState::kSilent || next == PeerState::kGone) && last_heard_ns != 0 ? last_heard_ns
                                                                                               : now_ns;
    state_ = next;
  }
  return state_;
}

std::string PeerMonitor::describe() const {
  return std::string(peerStateName(state_)) + " for " + formatDuration(seconds());
}

std::string formatDuration(double seconds) {
  char text[64];
  if (!(seconds >= 0) || !std::isfinite(seconds)) seconds = 0;
  if (seconds < 60) {
    std::snprintf(text, sizeof(text), "%.1f s", seconds);
  } else if (seconds < 3600) {
    std::snprintf(text, sizeof(text), "%d min %02d s", int(seconds) / 60, int(seconds) % 60);
  } else {
    std::snprintf(text, sizeof(text), "%d h %02d min", int(seconds) / 3600, int(seconds) % 3600 / 60);
  }
  return text;
}

}  // namespace telesphere::console::supervision
