// SPDX-License-Identifier: MIT
/// @brief LatencyRecord: exact samples up to the capacity, a log-spaced histogram throughout.
#include "xr/video/latency_record.h"

#include <algorithm>
#include <cmath>

namespace telesphere::xr::video {
namespace {

const double kLogRatio = std::log(LatencyRecord::kBinRatio);
const int kBins = static_cast<int>(std::ceil(std::log(LatencyRecord::kLargestMs / LatencyRecord::kSmallestMs) / kLogRatio));

int binOf(double ms) {
  if (!(ms > LatencyRecord::kSmallestMs)) return 0;
  if (!(ms < LatencyRecord::kLargestMs)) return kBins - 1;  // infinity too
  return std::min(static_cast<int>(std::log(ms / LatencyRecord::kSmallestMs) / kLogRatio), kBins - 1);
}

}  // namespace

LatencyRecord::LatencyRecord(std::size_t exact_capacity) : exact_capacity_(exact_capacity), bins_(static_cast<std::size_t>(kBins), 0) {}

void LatencyRecord::add(double ms) {
  if (std::isnan(ms)) return;
  if (exact_.size() < exact_capacity_) exact_.push_back(ms);
  ++bins_[static_cast<std::size_t>(binOf(ms))];
  smallest_ = n_ == 0 ? ms : std::min(smallest_, ms);
  largest_ = n_ == 0 ? ms : std::max(largest_, ms);
  ++n_;
}

double LatencyRecord::percentileFromBins(double q) const {
  // The nearest rank (as latencyFigure), then the bin holding it: its geometric middle.
  const auto k = static_cast<std::uint64_t>(q * static_cast<double>(n_ - 1) + 0.5);
  std::uint64_t below = 0;
  for (int b = 0; b < kBins; ++b) {
    below += bins_[static_cast<std::size_t>(b)];
    if (below > k) {
      const double middle = kSmallestMs * std::exp((b + 0.5) * kLogRatio);
      return std::clamp(middle, smallest_, largest_);
    }
  }
  return largest_;
}

LatencyFigure LatencyRecord::figure() const {
  if (n_ <= exact_.size()) return latencyFigure(exact_);
  LatencyFigure f;
  f.n = n_;
  f.p50_ms = percentileFromBins(0.5);
  f.p99_ms = percentileFromBins(0.99);
  return f;
}

std::size_t LatencyRecord::bytesHeld() const {
  return exact_.capacity() * sizeof(double) + bins_.capacity() * sizeof(std::uint64_t);
}

}  // namespace telesphere::xr::video
