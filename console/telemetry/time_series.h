// SPDX-License-Identifier: MIT
/// @brief One plotted quantity: (t, value) samples in time order, trimmed to a time window
///        (DESIGN.md §1, §7). Qt-free. Drawing goes through ColumnDecimator (column_decimator.h).
///
/// Storage is a deque: O(1) append at the back and trim at the front, no reallocation of the
/// whole buffer (as PlotJuggler keeps its streaming buffers). Range queries are binary searches on
/// time. A sample older than the newest is inserted in order (rare: one source per series) and
/// changes revision(), as clear() does, so cached decimations know to start again. Samples keep
/// an absolute index (position + removed()) across trimming.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <utility>
#include <vector>

namespace telesphere::console::telemetry {

struct Sample {
  double t = 0.0;  ///< s, the console's plot clock
  double v = 0.0;
};

class TimeSeries {
 public:
  /// `max_gap_s` > 0: consecutive samples further apart than this are not joined.
  explicit TimeSeries(double max_gap_s = 0.5) : max_gap_s_(max_gap_s) {}

  /// Adds a sample; NaN or infinite t is ignored. Equal times are kept in arrival order.
  void append(double t, double v);
  /// Drops every sample older than t.
  void trimBefore(double t);
  /// Keeps the newest `n` samples at most.
  void keepNewest(std::size_t n);
  void clear();

  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  const Sample& front() const { return samples_.front(); }
  const Sample& back() const { return samples_.back(); }
  const Sample& operator[](std::size_t i) const { return samples_[i]; }
  double maxGap() const { return max_gap_s_; }

  /// [first, last) indices of the samples with t0 ≤ t ≤ t1.
  std::pair<std::size_t, std::size_t> indexRange(double t0, double t1) const;
  /// Samples dropped from the front so far: sample i has the absolute index removed() + i.
  std::uint64_t removed() const { return removed_; }
  /// Changes when samples change other than by appending at the back or trimming the front.
  std::uint64_t revision() const { return revision_; }
  /// Memory the samples take (what the deque has allocated for them, approximately).
  std::size_t bytes() const;

 private:
  std::deque<Sample> samples_;
  double max_gap_s_;
  std::uint64_t removed_ = 0;
  std::uint64_t revision_ = 0;
};

}  // namespace telesphere::console::telemetry
