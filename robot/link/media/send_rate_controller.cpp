// SPDX-License-Identifier: MIT
/// @brief SendRateController: reports → delivered rate, loss, queuing delay, trend → target.
#include "robot/link/media/send_rate_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace telesphere::link::media {

std::string checkSendRateOptions(const SendRateOptions& o) {
  if (!(o.min_bps > 0) || !(o.min_bps <= o.initial_bps) || !(o.initial_bps <= o.max_bps))
    return "rates must satisfy 0 < min_bps <= initial_bps <= max_bps";
  if (!(o.backoff > 0 && o.backoff < 1) || !(o.min_backoff > 0 && o.min_backoff <= o.backoff))
    return "backoff must be in (0, 1) and min_backoff in (0, backoff]";
  if (!(o.growth_near_per_s >= 1) || !(o.growth_far_per_s >= o.growth_near_per_s))
    return "growth must satisfy 1 <= growth_near_per_s <= growth_far_per_s";
  if (!(o.near_band >= 0) || !(o.loss_congestive > 0 && o.loss_congestive <= 1) || !(o.max_over_delivered >= 1) ||
      !(o.headroom_bps >= 0))
    return "near_band >= 0, loss_congestive in (0, 1], max_over_delivered >= 1, headroom_bps >= 0";
  if (o.drain_ns <= 0 || o.queue_overuse_ns <= 0 || o.near_hold_ns < 0 || o.decrease_interval_ns < 0 || o.rate_window_ns <= 0 ||
      o.loss_window_ns <= 0 || o.reorder_window_ns < 0 || o.base_delay_window_ns <= 0)
    return "time windows must be positive";
  return checkDelayTrendOptions(o.trend);
}

std::string_view rateDecisionName(RateDecision d) {
  switch (d) {
    case RateDecision::kIncreaseNear: return "increase_near";
    case RateDecision::kIncreaseFar: return "increase_far";
    case RateDecision::kDecreaseOveruse: return "decrease_overuse";
    case RateDecision::kDecreaseLoss: return "decrease_loss";
    case RateDecision::kHoldUnderuse: return "hold_underuse";
    case RateDecision::kHoldAfterDecrease: return "hold_after_decrease";
    case RateDecision::kRestoreAfterDrain: return "restore_after_drain";
    case RateDecision::kHoldDraining: return "hold_draining";
    case RateDecision::kLimitedByDelivery: return "limited_by_delivery";
    case RateDecision::kLimitedByCap: return "limited_by_cap";
    case RateDecision::kCount: break;
  }
  return "unknown";
}

SendRateController::SendRateController(SendRateOptions options)
    : options_(options), trend_(options.trend), target_bps_(options.initial_bps) {
  if (const std::string why = checkSendRateOptions(options_); !why.empty())
    throw std::invalid_argument("SendRateOptions: " + why);
  stats_.target_bps = target_bps_;
}

void SendRateController::setCapBps(double cap_bps) {
  cap_bps_ = cap_bps > 0 ? std::max(cap_bps, options_.min_bps) : 0;
  const double max = cap_bps_ > 0 ? std::min(cap_bps_, options_.max_bps) : options_.max_bps;
  target_bps_ = std::min(target_bps_, max);
  stats_.target_bps = target_bps_;
}

void SendRateController::onPacketSent(std::uint32_t seq, std::int64_t send_ns, std::size_t bytes) {
  if (sent_.empty() || seq != first_seq_ + static_cast<std::uint32_t>(sent_.size())) {
    // The first datagram, or the sender's numbering jumped: start the bookkeeping afresh.
    sent_.clear();
    first_seq_ = seq;
  }
  sent_.push_back({send_ns, static_cast<std::uint32_t>(bytes), false});
}

void SendRateController::onFeedback(std::span<const PacketReport> reports, std::int64_t now_ns,
                                    std::int64_t last_hold_ns) {
  std::optional<std::int64_t> newest_send_ns;
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const PacketReport& r = reports[i];
    const std::uint32_t index = r.seq - first_seq_;
    if (index >= sent_.size() || sent_[index].reported) {
      ++stats_.reports_unknown;
      continue;
    }
    Sent& s = sent_[index];
    if (i + 1 == reports.size() && last_hold_ns >= 0) {
      // Sent at send_ns, answered last_hold_ns after it arrived, the answer here at now_ns.
      const double rtt_ms = static_cast<double>(now_ns - s.send_ns - last_hold_ns) * 1e-6;
      if (rtt_ms >= 0) {
        stats_.rtt_last_ms = rtt_ms;
        stats_.rtt_ms = stats_.rtt_ms < 0 ? rtt_ms : stats_.rtt_ms + (rtt_ms - stats_.rtt_ms) / 8.0;
      }
    }
    s.reported = true;
    ++stats_.packets_reported;
    arrivals_.emplace_back(r.arrival_ns, s.bytes);
    trend_.onPacket(s.send_ns, r.arrival_ns);
    loss_events_.emplace_back(now_ns, false);
    // The one-way delay with the clocks' offset in it; only its excess over the minimum is used.
    const std::int64_t raw = r.arrival_ns - s.send_ns;
    const std::int64_t slot = s.send_ns / 1'000'000'000;
    if (delay_minima_.empty() || delay_minima_.back().first != slot) delay_minima_.emplace_back(slot, raw);
    else delay_minima_.back().second = std::min(delay_minima_.back().second, raw);
    last_raw_delay_ns_ = raw;
    newest_send_ns = std::max(newest_send_ns.value_or(s.send_ns), s.send_ns);
    newest_reported_send_ns_ = std::max(newest_reported_send_ns_, s.send_ns);
  }
  if (newest_send_ns) countLosses(*newest_send_ns, now_ns);
  // Datagrams nobody reported for long (the reports themselves were lost, or the receiver left).
  while (!sent_.empty() && sent_.front().send_ns < now_ns - 2'000'000'000) {
    if (!sent_.front().reported) {
      ++stats_.packets_lost;
      loss_events_.emplace_back(now_ns, true);
    }
    sent_.pop_front();
    ++first_seq_;
  }
  if (!arrivals_.empty()) {
    const std::int64_t newest = arrivals_.back().first;
    while (!arrivals_.empty() && arrivals_.front().first < newest - options_.rate_window_ns) arrivals_.pop_front();
  }
  const std::int64_t slots = options_.base_delay_window_ns / 1'000'000'000 + 1;
  while (!delay_minima_.empty() && delay_minima_.front().first < delay_minima_.back().first - slots + 1)
    delay_minima_.pop_front();
  update(now_ns);
}

void SendRateController::countLosses(std::int64_t newest_reported_send_ns, std::int64_t now_ns) {
  while (!sent_.empty()) {
    const Sent& s = sent_.front();
    if (!s.reported) {
      if (s.send_ns >= newest_reported_send_ns - options_.reorder_window_ns) break;
      ++stats_.packets_lost;
      loss_events_.emplace_back(now_ns, true);
    }
    sent_.pop_front();
    ++first_seq_;
  }
}

double SendRateController::deliveredBps() const {
  if (arrivals_.size() < 2) return 0;
  const std::int64_t span = arrivals_.back().first - arrivals_.front().first;
  if (span < options_.rate_window_ns / 4) return 0;
  double bytes = 0;
  for (std::size_t i = 1; i < arrivals_.size(); ++i) bytes += arrivals_[i].second;
  return 8.0 * bytes * 1e9 / static_cast<double>(span);
}

double SendRateController::lossFraction(std::int64_t now_ns) {
  while (!loss_events_.empty() && loss_events_.front().first < now_ns - options_.loss_window_ns) loss_events_.pop_front();
  if (loss_events_.empty()) return 0;
  const auto lost = std::count_if(loss_events_.begin(), loss_events_.end(), [](const auto& e) { return e.second; });
  return static_cast<double>(lost) / static_cast<double>(loss_events_.size());
}

void SendRateController::update(std::int64_t now_ns) {
  const double dt_s = last_update_ns_ ? static_cast<double>(now_ns - *last_update_ns_) * 1e-9 : 0.0;
  last_update_ns_ = now_ns;
  const PathUsage usage = trend_.usage();
  const double delivered = deliveredBps();
  const double loss = lossFraction(now_ns);
  std::int64_t base_delay = std::numeric_limits<std::int64_t>::max();
  for (const auto& [slot, minimum] : delay_minima_) base_delay = std::min(base_delay, minimum);
  const double queue_ns = delay_minima_.empty() ? 0.0 : static_cast<double>(last_raw_delay_ns_ - base_delay);
  // One decrease per round trip: not before a report shows a datagram sent after the last one.
  // Sooner when the path delivers far less than the target: the rate fell under us, and a deep
  // queue would stretch that round trip by its own length.
  const bool far_above_delivered = delivered > 0 && target_bps_ > 1.5 * delivered;
  const bool may_decrease =
      !last_decrease_ns_ || (now_ns - *last_decrease_ns_ >= options_.decrease_interval_ns &&
                             (newest_reported_send_ns_ > *last_decrease_ns_ || far_above_delivered));
  const double before = target_bps_;

  // A standing queue says over-use once; again only if it grew since (while it drains it must not
  // push the rate down decrease after decrease).
  const bool deep_queue = queue_ns > static_cast<double>(options_.queue_overuse_ns) &&
                          (!queue_at_decrease_ns_ || queue_ns > *queue_at_decrease_ns_ + 10e6);
  if (usage == PathUsage::kOveruse || deep_queue) {
    if (may_decrease) {
      const double base = delivered > 0 ? delivered : target_bps_;
      const double factor =
          std::clamp(1.0 - queue_ns / static_cast<double>(options_.drain_ns), options_.min_backoff, options_.backoff);
      target_bps_ = std::min(target_bps_, factor * base);
      // Below the usual back-off only to drain a standing queue: once it is gone, back to there.
      if (factor < options_.backoff) drain_restore_bps_ = options_.backoff * base;
      overuse_rate_bps_ = base;
      last_decrease_ns_ = now_ns;
      queue_at_decrease_ns_ = queue_ns;
      near_since_ns_.reset();
      decide(RateDecision::kDecreaseOveruse);
    } else {
      decide(RateDecision::kHoldAfterDecrease);
    }
  } else if (loss > options_.loss_congestive && may_decrease) {
    target_bps_ *= 1.0 - loss / 2;
    last_decrease_ns_ = now_ns;
    decide(RateDecision::kDecreaseLoss);
  } else if (drain_restore_bps_ && queue_ns < static_cast<double>(options_.queue_overuse_ns) / 2) {
    target_bps_ = std::max(target_bps_, *drain_restore_bps_);
    drain_restore_bps_.reset();
    queue_at_decrease_ns_.reset();
    decide(RateDecision::kRestoreAfterDrain);
  } else if (usage == PathUsage::kUnderuse) {
    if (queue_ns < static_cast<double>(options_.queue_overuse_ns) / 2) queue_at_decrease_ns_.reset();
    decide(RateDecision::kHoldUnderuse);
  } else if (drain_restore_bps_) {
    decide(RateDecision::kHoldDraining);
  } else {
    if (queue_ns < static_cast<double>(options_.queue_overuse_ns) / 2) queue_at_decrease_ns_.reset();
    bool near = overuse_rate_bps_ && target_bps_ > *overuse_rate_bps_ * (1 - options_.near_band) &&
                target_bps_ < *overuse_rate_bps_ * (1 + options_.near_band);
    if (near) {
      if (!near_since_ns_) near_since_ns_ = now_ns;
      if (now_ns - *near_since_ns_ >= options_.near_hold_ns) {
        // Near the old limit for long without over-use: the path has grown; probe again.
        overuse_rate_bps_.reset();
        near_since_ns_.reset();
        near = false;
      }
    } else {
      near_since_ns_.reset();
    }
    target_bps_ *= std::pow(near ? options_.growth_near_per_s : options_.growth_far_per_s, dt_s);
    RateDecision d = near ? RateDecision::kIncreaseNear : RateDecision::kIncreaseFar;
    // Nothing delivered in the window (a source slower than it, or idle) is no evidence that the
    // path carries more: hold. Otherwise never far above what arrived.
    const double limit = delivered > 0 ? options_.max_over_delivered * delivered + options_.headroom_bps : before;
    if (target_bps_ > limit) {
      target_bps_ = std::max(before, limit);
      d = RateDecision::kLimitedByDelivery;
    }
    const double max = cap_bps_ > 0 ? std::min(cap_bps_, options_.max_bps) : options_.max_bps;
    if (target_bps_ > max) {
      target_bps_ = max;
      d = RateDecision::kLimitedByCap;
    }
    decide(d);
  }
  target_bps_ = std::max(target_bps_, options_.min_bps);
  stats_.target_bps = target_bps_;
  stats_.delivered_bps = delivered;
  stats_.loss_fraction = loss;
  stats_.queue_delay_ms = queue_ns * 1e-6;
  stats_.usage = usage;
}

}  // namespace telesphere::link::media
