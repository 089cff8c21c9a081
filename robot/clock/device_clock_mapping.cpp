// SPDX-License-Identifier: MIT
/// @brief DeviceClockMapping: lower-envelope fit of hardware stamps to host arrival times.
#include "robot/clock/device_clock_mapping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace telesphere::robot::clock {

DeviceClockMapping::DeviceClockMapping(DeviceClockMappingOptions options) : options_(options) {
  options_.window = std::max(options_.window, 2);
  options_.late_pairs_for_reset = std::max(options_.late_pairs_for_reset, 1);
}

void DeviceClockMapping::reset() {
  pairs_.clear();
  ref_ = {0, 0};
  offset_ = 0;
  slope_ = 0;
  late_run_ = 0;
}

std::int64_t DeviceClockMapping::toHostNs(std::int64_t hw_ns) const {
  const std::int64_t dx = hw_ns - ref_.hw_ns;
  return ref_.host_ns + dx + std::llround(offset_ + slope_ * static_cast<double>(dx));
}

std::int64_t DeviceClockMapping::hwToHostOffsetNs() const {
  return ref_.host_ns - ref_.hw_ns + std::llround(offset_);
}

DeviceClockMapping::AddResult DeviceClockMapping::add(std::int64_t hw_ns, std::int64_t host_arrival_ns) {
  AddResult result = AddResult::kAdded;
  if (!pairs_.empty()) {
    bool jump = hw_ns <= pairs_.back().hw_ns;
    if (!jump) {
      const std::int64_t residual_ns = host_arrival_ns - toHostNs(hw_ns);
      if (residual_ns < -options_.jump_threshold_ns) {
        jump = true;
      } else if (residual_ns > options_.jump_threshold_ns) {
        if (++late_run_ < options_.late_pairs_for_reset) return AddResult::kLateSkipped;
        jump = true;
      } else {
        late_run_ = 0;
      }
    }
    if (jump) {
      reset();
      ++jumps_;
      result = AddResult::kReset;
    }
  }
  pairs_.push_back({hw_ns, host_arrival_ns});
  while (pairs_.size() > static_cast<std::size_t>(options_.window)) pairs_.pop_front();
  refit();
  return result;
}

void DeviceClockMapping::refit() {
  ref_ = pairs_.back();
  // Points (x, y) = (t_hw − ref.hw, (t_host − ref.host) − (t_hw − ref.hw)), x ascending.
  struct Point {
    double x, y;
  };
  std::vector<Point> hull;
  hull.reserve(pairs_.size());
  double mean_x = 0;
  for (const Pair& p : pairs_) {
    const std::int64_t dx = p.hw_ns - ref_.hw_ns;
    const Point q{static_cast<double>(dx), static_cast<double>((p.host_ns - ref_.host_ns) - dx)};
    mean_x += q.x;
    // Lower convex hull (Andrew's monotone chain): drop points that do not turn left.
    while (hull.size() >= 2) {
      const Point& o = hull[hull.size() - 2];
      const Point& a = hull.back();
      if ((a.x - o.x) * (q.y - o.y) - (a.y - o.y) * (q.x - o.x) > 0) break;
      hull.pop_back();
    }
    hull.push_back(q);
  }
  mean_x /= static_cast<double>(pairs_.size());

  double slope = 0;
  for (std::size_t i = 0; i + 1 < hull.size(); ++i) {
    if (hull[i + 1].x >= mean_x || i + 2 == hull.size()) {
      slope = (hull[i + 1].y - hull[i].y) / (hull[i + 1].x - hull[i].x);
      break;
    }
  }
  const double max_slope = options_.max_drift_ppm * 1e-6;
  slope_ = std::clamp(slope, -max_slope, max_slope);

  // Highest line of that slope with every pair on or above it.
  double offset = std::numeric_limits<double>::infinity();
  for (const Pair& p : pairs_) {
    const std::int64_t dx = p.hw_ns - ref_.hw_ns;
    const double y = static_cast<double>((p.host_ns - ref_.host_ns) - dx);
    offset = std::min(offset, y - slope_ * static_cast<double>(dx));
  }
  offset_ = offset;
}

}  // namespace telesphere::robot::clock
