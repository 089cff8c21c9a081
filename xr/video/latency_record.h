// SPDX-License-Identifier: MIT
/// @brief A whole session's latency samples (render time, image age, upload, the depth hold) in
///        bounded memory. The operator app runs for hours at 90 Hz and more: a vector of every
///        sample grew by ~13 MB an hour and, on the render thread, copied itself whole each time
///        it doubled. The record keeps the first samples exactly (the figures are then
///        latencyFigure's, to the digit: a test or a short run sees no change) and counts every
///        sample in a histogram of bins 1 % wide, from which the figures come beyond that: within
///        0.5 % of the nearest-rank value, clamped to the smallest and largest sample.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "xr/video/latency_figure.h"

namespace telesphere::xr::video {

class LatencyRecord {
 public:
  /// The histogram's range (ms): samples below the first bin or above the last count at its edge.
  static constexpr double kSmallestMs = 1e-3, kLargestMs = 1e6;
  /// Each bin's upper edge over its lower.
  static constexpr double kBinRatio = 1.01;

  /// `exact_capacity`: how many samples are kept as they are (64 Ki: 12 min at 90 Hz, 512 KiB).
  explicit LatencyRecord(std::size_t exact_capacity = std::size_t{1} << 16);

  /// A sample (ms); NaN is ignored.
  void add(double ms);
  /// Median and 99th percentile of every sample added (n: how many).
  LatencyFigure figure() const;
  std::size_t size() const { return n_; }
  /// Bytes held, for the bound's test: the same after the capacity is reached, however many more.
  std::size_t bytesHeld() const;

 private:
  double percentileFromBins(double q) const;

  std::size_t exact_capacity_;
  std::vector<double> exact_;
  std::vector<std::uint64_t> bins_;
  std::size_t n_ = 0;
  double smallest_ = 0, largest_ = 0;
};

}  // namespace telesphere::xr::video
