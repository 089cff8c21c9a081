// SPDX-License-Identifier: MIT
/// @brief TimeSeries: ordered deque, binary-search ranges, absolute indices.
#include "console/telemetry/time_series.h"

#include <algorithm>
#include <cmath>

namespace telesphere::console::telemetry {
namespace {

bool earlier(const Sample& s, double t) { return s.t < t; }
bool later(double t, const Sample& s) { return t < s.t; }

}  // namespace

void TimeSeries::append(double t, double v) {
  if (!std::isfinite(t)) return;
  if (samples_.empty() || t >= samples_.back().t) {
    samples_.push_back({t, v});
    return;
  }
  const auto at = std::upper_bound(samples_.begin(), samples_.end(), t, later);
  samples_.insert(at, Sample{t, v});
  ++revision_;
}

void TimeSeries::clear() {
  removed_ += samples_.size();
  samples_.clear();
  ++revision_;
}

void TimeSeries::trimBefore(double t) {
  while (!samples_.empty() && samples_.front().t < t) {
    samples_.pop_front();
    ++removed_;
  }
}

void TimeSeries::keepNewest(std::size_t n) {
  while (samples_.size() > n) {
    samples_.pop_front();
    ++removed_;
  }
}

std::pair<std::size_t, std::size_t> TimeSeries::indexRange(double t0, double t1) const {
  const auto first = std::lower_bound(samples_.begin(), samples_.end(), t0, earlier);
  const auto last = std::upper_bound(first, samples_.end(), t1, later);
  return {std::size_t(first - samples_.begin()), std::size_t(last - samples_.begin())};
}

std::size_t TimeSeries::bytes() const {
  // libstdc++ deques allocate 512-byte blocks plus a map of block pointers.
  constexpr std::size_t kBlock = 512;
  const std::size_t per_block = kBlock / sizeof(Sample);
  const std::size_t blocks = samples_.size() / per_block + 2;
  return blocks * (kBlock + sizeof(void*));
}

}  // namespace telesphere::console::telemetry
