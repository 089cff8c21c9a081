// SPDX-License-Identifier: MIT
#include "robot/link/delay_trend.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace telesphere::link {

std::string checkDelayTrendOptions(const DelayTrendOptions& o) {
  if (o.group_ns < 0) return "the group span must be ≥ 0";
  if (o.window < 2) return "the regression needs a window of at least 2 groups";
  if (!(o.smoothing >= 0 && o.smoothing < 1)) return "the smoothing must be in [0, 1)";
  if (!(o.gain > 0 && o.initial_threshold_ms > 0 && o.k_up >= 0 && o.k_down >= 0))
    return "gain and threshold must be > 0, the adaptation rates ≥ 0";
  if (o.overuse_ns < 0) return "the over-use time must be ≥ 0";
  return {};
}

const char* pathUsageName(PathUsage usage) {
  switch (usage) {
    case PathUsage::kNormal: return "normal";
    case PathUsage::kOveruse: return "over-use";
    case PathUsage::kUnderuse: return "under-use";
  }
  return "?";
}

DelayTrendDetector::DelayTrendDetector(DelayTrendOptions options)
    : options_(std::move(options)), threshold_ms_(options_.initial_threshold_ms) {
  assert(checkDelayTrendOptions(options_).empty());
}

PathUsage DelayTrendDetector::onPacket(std::int64_t send_ns, std::int64_t arrival_ns) {
  if (!current_) {
    current_ = Group{send_ns, send_ns, arrival_ns};
    first_arrival_ns_ = arrival_ns;
    return usage_;
  }
  if (send_ns < current_->first_send_ns) return usage_;  // reordered from an earlier group
  if (send_ns - current_->first_send_ns <= options_.group_ns) {
    current_->last_send_ns = std::max(current_->last_send_ns, send_ns);
    current_->last_arrival_ns = std::max(current_->last_arrival_ns, arrival_ns);
    return usage_;
  }
  closeGroup(*current_);
  current_ = Group{send_ns, send_ns, arrival_ns};
  return usage_;
}

void DelayTrendDetector::closeGroup(const Group& group) {
  if (previous_) {
    const double delta_ms = 1e-6 * static_cast<double>((group.last_arrival_ns - previous_->last_arrival_ns) -
                                                       (group.last_send_ns - previous_->last_send_ns));
    accumulated_ms_ += delta_ms;
    smoothed_ms_ = options_.smoothing * smoothed_ms_ + (1 - options_.smoothing) * accumulated_ms_;
    ++groups_seen_;
    points_.emplace_back(1e-6 * static_cast<double>(group.last_arrival_ns - first_arrival_ns_), smoothed_ms_);
    if (points_.size() > static_cast<std::size_t>(options_.window)) points_.pop_front();
    if (points_.size() == static_cast<std::size_t>(options_.window)) {
      double mean_x = 0, mean_y = 0;
      for (const auto& [x, y] : points_) {
        mean_x += x;
        mean_y += y;
      }
      mean_x /= static_cast<double>(points_.size());
      mean_y /= static_cast<double>(points_.size());
      double numerator = 0, denominator = 0;
      for (const auto& [x, y] : points_) {
        numerator += (x - mean_x) * (y - mean_y);
        denominator += (x - mean_x) * (x - mean_x);
      }
      if (denominator > 0) slope_ = numerator / denominator;
      if (slope_) detect(group.last_arrival_ns);
    }
  }
  previous_ = group;
}

void DelayTrendDetector::detect(std::int64_t now_ns) {
  modified_trend_ms_ = std::min(groups_seen_, 60) * *slope_ * options_.gain;
  if (modified_trend_ms_ > threshold_ms_) {
    if (!above_since_ns_) above_since_ns_ = now_ns;
    if (now_ns - *above_since_ns_ >= options_.overuse_ns && modified_trend_ms_ >= previous_trend_ms_)
      usage_ = PathUsage::kOveruse;
  } else {
    above_since_ns_.reset();
    usage_ = modified_trend_ms_ < -threshold_ms_ ? PathUsage::kUnderuse : PathUsage::kNormal;
  }
  previous_trend_ms_ = modified_trend_ms_;
  // The threshold follows the trend's own size, slowly upward and faster downward; a trend far
  // outside it (a route change, a spike) does not move it.
  const double magnitude = std::fabs(modified_trend_ms_);
  if (last_threshold_update_ns_ != 0 && magnitude <= threshold_ms_ + 15.0) {
    const double k = magnitude < threshold_ms_ ? options_.k_down : options_.k_up;
    const double dt_ms = std::min(100.0, 1e-6 * static_cast<double>(now_ns - last_threshold_update_ns_));
    threshold_ms_ = std::clamp(threshold_ms_ + dt_ms * k * (magnitude - threshold_ms_), 6.0, 600.0);
  }
  last_threshold_update_ns_ = now_ns;
}

}  // namespace telesphere::link
