// SPDX-License-Identifier: MIT
/// @brief Is the path's queue growing? The delay-gradient detector of a delay-based bandwidth
///        estimate (DESIGN.md §9), after the trendline filter of WebRTC's congestion control
///        (Carlucci et al., "Analysis and design of the Google congestion control", MMSys 2016):
///        packets are grouped by send time (bursts within `group_ns`); between consecutive groups
///        the one-way delay variation d = (a_i − a_{i−1}) − (s_i − s_{i−1}) is accumulated and
///        exponentially smoothed; the slope of the smoothed accumulated delay against arrival time
///        over the last `window` groups (least squares) is the queue's growth in ms per ms. It
///        is compared, scaled by min(groups, 60) · `gain`, with a threshold γ that adapts to the
///        path's noise (γ ← γ + Δt · k · (|m| − γ), k = k_up above γ, k_down below; 6–600 ms):
///        above γ for `overuse_ns` and still rising is over-use, below −γ under-use. Send and
///        arrival times are on two clocks: only differences enter, so their offset cancels.
///        Loss does not enter: a path that loses without queuing stays "normal".
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace telesphere::link {

struct DelayTrendOptions {
  std::int64_t group_ns = 5'000'000;  ///< packets sent within this of a group's first are one group
  int window = 20;                    ///< groups in the regression
  double smoothing = 0.9;             ///< of the previous smoothed value
  double gain = 4.0;
  double initial_threshold_ms = 12.5;
  double k_up = 0.0087, k_down = 0.039;
  std::int64_t overuse_ns = 10'000'000;  ///< above the threshold this long before over-use is said
};

std::string checkDelayTrendOptions(const DelayTrendOptions& options);

enum class PathUsage { kNormal, kOveruse, kUnderuse };
const char* pathUsageName(PathUsage usage);

class DelayTrendDetector {
 public:
  /// Options must pass checkDelayTrendOptions (asserted in debug builds).
  explicit DelayTrendDetector(DelayTrendOptions options = {});

  /// One packet: when it was sent (sender clock) and when it arrived (receiver clock), ns. Packets
  /// are given in arrival order; one sent before its group's first (reordered) is ignored.
  PathUsage onPacket(std::int64_t send_ns, std::int64_t arrival_ns);

  PathUsage usage() const { return usage_; }
  /// The last regression slope (ms of queue growth per ms), and the scaled trend and threshold
  /// it was compared with (ms); nothing before `window` groups.
  std::optional<double> slope() const { return slope_; }
  double modifiedTrendMs() const { return modified_trend_ms_; }
  double thresholdMs() const { return threshold_ms_; }

 private:
  struct Group {
    std::int64_t first_send_ns = 0, last_send_ns = 0, last_arrival_ns = 0;
  };
  void closeGroup(const Group& group);
  void detect(std::int64_t now_ns);

  DelayTrendOptions options_;
  std::optional<Group> current_, previous_;
  std::int64_t first_arrival_ns_ = 0;
  double accumulated_ms_ = 0, smoothed_ms_ = 0;
  int groups_seen_ = 0;
  std::deque<std::pair<double, double>> points_;  ///< (arrival ms since the first, smoothed delay ms)
  std::optional<double> slope_;
  double modified_trend_ms_ = 0, previous_trend_ms_ = 0;
  double threshold_ms_;
  std::int64_t last_threshold_update_ns_ = 0;
  std::optional<std::int64_t> above_since_ns_;
  PathUsage usage_ = PathUsage::kNormal;
};

}  // namespace telesphere::link
