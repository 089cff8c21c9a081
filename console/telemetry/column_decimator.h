// SPDX-License-Identifier: MIT
/// @brief Min/max-per-pixel-column decimation of one TimeSeries for drawing, kept between redraws
///        (DESIGN.md §7: the plots never draw raw data). Qt-free.
///
/// Columns are `width` seconds wide and aligned to multiples of it in absolute time: column k
/// holds the samples with k·width ≤ t < (k+1)·width. From each column the smallest and the
/// largest sample are kept, in time order, so the drawn polyline spans in every pixel column
/// exactly the values the full data spans there (joins between columns stay within the two
/// columns' ranges): ≤ 2 points per column whatever the input rate. A gap — consecutive samples
/// further apart than the series' maxGap() — splits its column into runs decimated apart and
/// leaves a NaN sample between them, so a plot breaks the line there (a lost link shows as a gap).
///
/// Because the grid is fixed in time, a column is final once a sample of a later column exists
/// (samples arrive in time order): while a live view scrolls, only new samples are looked at and
/// a redraw costs O(visible columns + new samples), not O(visible samples). A different width, a
/// different series, or a series revision (an out-of-order insert, clear) starts afresh.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "console/telemetry/time_series.h"

namespace telesphere::console::telemetry {

class ColumnDecimator {
 public:
  /// The decimation of the columns that overlap [t0, t1], plus one column on each side (so lines
  /// reach the edges), into `out` (cleared first). width > 0, t1 ≥ t0.
  void decimate(const TimeSeries& series, double t0, double t1, double width, std::vector<Sample>& out);

  /// Columns held final (for tests and the benchmark).
  std::size_t cachedColumns() const { return closed_.size(); }
  /// Samples looked at by the last decimate() (new ones and the open column's).
  std::size_t lastSamplesScanned() const { return last_scanned_; }

 private:
  struct Column {
    long long k;
    std::vector<Sample> points;  ///< min/max of each run, NaN between runs
  };

  void reset(const TimeSeries& series, double width, long long k_first);

  const TimeSeries* series_ = nullptr;
  double width_ = 0.0;
  std::uint64_t revision_ = 0;
  long long first_k_ = 0;  ///< the leftmost column covered since the last reset
  std::deque<Column> closed_;
  std::uint64_t next_ = 0;  ///< absolute index of the first sample not in a closed column
  bool have_previous_ = false;
  double previous_t_ = 0.0;  ///< the last sample folded into a closed column (for gaps)
  std::size_t last_scanned_ = 0;
};

}  // namespace telesphere::console::telemetry
