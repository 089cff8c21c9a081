// SPDX-License-Identifier: MIT
/// @brief How fast the media path may send (DESIGN.md §9): a delay-based estimate that the
///        stream settings follow. The receiver reports, for each datagram, its sequence number and
///        arrival time; from those the controller knows the queuing-delay trend (DelayTrendDetector),
///        the rate the path delivered, the queuing delay above the path's minimum and the loss.
///
///        - over-use (the queue grows, or stands deeper than queue_overuse_ns): target ← factor ·
///          delivered rate, factor 0.85, lower when a queue is already standing (1 − queue /
///          drain_ns, not below min_backoff), so a rate that fell under us is drained within about
///          drain_ns instead of at 15 % of the new rate;
///          at most one decrease per round trip (a report of a datagram sent after the last one);
///          once a queue drained below queue_overuse_ns / 2, back to backoff · that rate;
///        - under-use (the queue drains): hold;
///        - normal: grow, multiplicatively, slowly (growth_near_per_s) within ±near_band of the
///          rate where the last over-use happened, fast (growth_far_per_s: probing, not
///          creeping) elsewhere and once near_hold_ns passed near it without over-use (the path
///          has grown);
///        - loss: below loss_congestive it is taken as the path's own (long links lose without
///          queuing); above it, target ← target · (1 − loss / 2);
///        - never above max_over_delivered × the delivered rate plus headroom_bps (a source that
///          sends less than it may does not push the target to the sky; nothing delivered in the
///          window holds it), nor the supervisor's cap.
///        Every decision is counted by its reason.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "robot/link/delay_trend.h"

namespace telesphere::link::media {

struct SendRateOptions {
  double initial_bps = 8e6;
  double min_bps = 0.5e6;
  double max_bps = 1e9;
  double backoff = 0.85;
  std::int64_t drain_ns = 250'000'000;
  double min_backoff = 0.1;
  /// A queue this deep is over-use whatever the trend says (a rate that fell under us fills the
  /// bottleneck's buffer before the trend has its 20 groups).
  std::int64_t queue_overuse_ns = 60'000'000;
  double growth_far_per_s = 2.5;
  double growth_near_per_s = 1.08;
  double near_band = 0.2;                 ///< within ± this fraction of the last over-use's rate: near
  std::int64_t near_hold_ns = 500'000'000;
  std::int64_t decrease_interval_ns = 200'000'000;  ///< at most one decrease per this
  double loss_congestive = 0.10;
  double max_over_delivered = 1.5;
  double headroom_bps = 1e6;
  std::int64_t rate_window_ns = 300'000'000;   ///< the delivered rate over this much arrival time
  std::int64_t loss_window_ns = 500'000'000;
  std::int64_t reorder_window_ns = 30'000'000;  ///< a datagram unreported while one sent this much later was: lost
  std::int64_t base_delay_window_ns = 10'000'000'000;
  DelayTrendOptions trend;
};

/// Nothing wrong: empty; else what is wrong.
std::string checkSendRateOptions(const SendRateOptions& options);

/// One datagram as the receiver saw it: its sequence number and its arrival (receiver's clock).
struct PacketReport {
  std::uint32_t seq = 0;
  std::int64_t arrival_ns = 0;
};

enum class RateDecision : int {
  kIncreaseNear,    ///< slow growth near the last over-use's rate
  kIncreaseFar,     ///< probing growth
  kDecreaseOveruse, ///< the queue grew
  kDecreaseLoss,    ///< loss above loss_congestive
  kHoldUnderuse,    ///< the queue drains
  kHoldAfterDecrease,  ///< over-use still said, but the last decrease has not shown yet
  kRestoreAfterDrain,  ///< a standing queue drained: back to the usual back-off from its rate
  kHoldDraining,       ///< a standing queue still drains
  kLimitedByDelivery,  ///< held at max_over_delivered × delivered (the source sends less)
  kLimitedByCap,       ///< held at the supervisor's cap or max_bps
  kCount
};
std::string_view rateDecisionName(RateDecision decision);

struct SendRateStats {
  double target_bps = 0;
  double delivered_bps = 0;
  double loss_fraction = 0;          ///< over loss_window_ns
  double queue_delay_ms = 0;         ///< the last one-way delay above the window's minimum
  double rtt_ms = -1;                ///< smoothed round trip (weight 1/8 per report); negative: none yet
  double rtt_last_ms = -1;           ///< the newest report's
  PathUsage usage = PathUsage::kNormal;
  std::uint64_t packets_reported = 0, packets_lost = 0, reports_unknown = 0;
  std::array<std::uint64_t, static_cast<int>(RateDecision::kCount)> decisions{};
  std::uint64_t decided(RateDecision d) const { return decisions[static_cast<int>(d)]; }
};

class SendRateController {
 public:
  /// Options must pass checkSendRateOptions (throws std::invalid_argument otherwise).
  explicit SendRateController(SendRateOptions options = {});

  /// A datagram left at send_ns (sender's steady clock); sequence numbers rise by one per datagram.
  void onPacketSent(std::uint32_t seq, std::int64_t send_ns, std::size_t bytes);
  /// The receiver's reports, arrival order, taken at now_ns (sender's clock). A report of a seq
  /// not sent, already reported or already counted lost is ignored (counted unknown).
  /// `last_hold_ns`: how long the last report waited at the receiver before it was sent (the
  /// report's hold); with it the last report gives a round trip sample (negative: none).
  void onFeedback(std::span<const PacketReport> reports, std::int64_t now_ns, std::int64_t last_hold_ns = -1);
  /// The supervisor's cap (0: none).
  void setCapBps(double cap_bps);

  double targetBps() const { return target_bps_; }
  const SendRateStats& stats() const { return stats_; }

 private:
  struct Sent {
    std::int64_t send_ns = 0;
    std::uint32_t bytes = 0;
    bool reported = false;
  };
  void countLosses(std::int64_t newest_reported_send_ns, std::int64_t now_ns);
  double deliveredBps() const;
  double lossFraction(std::int64_t now_ns);
  void update(std::int64_t now_ns);
  void decide(RateDecision d) { ++stats_.decisions[static_cast<int>(d)]; }

  SendRateOptions options_;
  DelayTrendDetector trend_;
  double target_bps_;
  double cap_bps_ = 0;
  std::uint32_t first_seq_ = 0;   ///< seq of sent_.front()
  std::deque<Sent> sent_;
  std::deque<std::pair<std::int64_t, std::uint32_t>> arrivals_;  ///< (arrival ns, bytes) in the rate window
  std::deque<std::pair<std::int64_t, bool>> loss_events_;        ///< (now ns, lost) in the loss window
  std::deque<std::pair<std::int64_t, std::int64_t>> delay_minima_;  ///< (send ns, min raw delay) per 1 s slot
  std::int64_t last_raw_delay_ns_ = 0;
  std::optional<std::int64_t> last_update_ns_, last_decrease_ns_, near_since_ns_;
  std::optional<double> overuse_rate_bps_;
  std::optional<double> queue_at_decrease_ns_;  ///< the queue when the last decrease was decided
  std::optional<double> drain_restore_bps_;     ///< where to go once a drained queue is gone
  std::int64_t newest_reported_send_ns_ = std::numeric_limits<std::int64_t>::min();
  SendRateStats stats_;
};

}  // namespace telesphere::link::media
