// SPDX-License-Identifier: MIT
/// @brief ColumnDecimator: final columns cached, the open one recomputed.
#include "console/telemetry/column_decimator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace telesphere::console::telemetry {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

long long columnOf(double t, double width) { return static_cast<long long>(std::floor(t / width)); }

/// The smallest and the largest sample of a run without gaps, emitted in time order (the first
/// of equal values wins).
struct Run {
  bool open = false;
  Sample min, max;

  void add(const Sample& s) {
    if (!open) {
      open = true;
      min = max = s;
      return;
    }
    if (s.v < min.v) min = s;
    if (s.v > max.v) max = s;
  }

  void flush(std::vector<Sample>& out) {
    if (!open) return;
    const bool min_first = min.t <= max.t;
    out.push_back(min_first ? min : max);
    if (min.t != max.t || min.v != max.v) out.push_back(min_first ? max : min);
    open = false;
  }
};

/// Folds one sample into `run`/`out`: a gap to the previous sample closes the run with a NaN
/// break; a NaN sample is a break of its own.
void fold(const Sample& s, double max_gap, bool& have_previous, double& previous_t, Run& run,
          std::vector<Sample>& out) {
  if (have_previous && s.t - previous_t > max_gap) {
    run.flush(out);
    out.push_back({0.5 * (s.t + previous_t), kNaN});
  }
  have_previous = true;
  previous_t = s.t;
  if (std::isnan(s.v)) {
    run.flush(out);
    out.push_back(s);
    return;
  }
  run.add(s);
}

}  // namespace

void ColumnDecimator::reset(const TimeSeries& series, double width, long long k_first) {
  series_ = &series;
  width_ = width;
  revision_ = series.revision();
  first_k_ = k_first;
  closed_.clear();
  const std::size_t i = series.indexRange(double(k_first) * width, std::numeric_limits<double>::infinity()).first;
  next_ = series.removed() + i;
  have_previous_ = i > 0;
  if (have_previous_) previous_t_ = series[i - 1].t;
}

void ColumnDecimator::decimate(const TimeSeries& series, double t0, double t1, double width,
                               std::vector<Sample>& out) {
  out.clear();
  last_scanned_ = 0;
  if (series.empty() || !(width > 0.0) || !(t1 >= t0)) return;
  const long long k_first = columnOf(t0, width) - 1;
  const long long k_last = columnOf(t1, width) + 1;
  if (series_ != &series || width != width_ || series.revision() != revision_ || next_ < series.removed() ||
      k_first < first_k_)
    reset(series, width, k_first);
  while (!closed_.empty() && closed_.front().k < k_first) closed_.pop_front();
  first_k_ = std::max(first_k_, k_first);

  // Fold the samples of every column before the newest one: those columns are final.
  const double max_gap = series.maxGap();
  const long long k_newest = columnOf(series.back().t, width);
  std::size_t i = std::size_t(next_ - series.removed());
  const std::size_t n = series.size();
  Run run;
  for (; i < n; ++i) {
    const Sample& s = series[i];
    const long long k = columnOf(s.t, width);
    if (k >= k_newest) break;
    if (closed_.empty() || closed_.back().k != k) {
      if (!closed_.empty()) run.flush(closed_.back().points);
      closed_.push_back({k, {}});
    }
    fold(s, max_gap, have_previous_, previous_t_, run, closed_.back().points);
    ++last_scanned_;
  }
  if (!closed_.empty()) run.flush(closed_.back().points);
  next_ = series.removed() + i;

  for (const Column& c : closed_) {
    if (c.k > k_last) break;
    if (c.k >= k_first) out.insert(out.end(), c.points.begin(), c.points.end());
  }
  // The newest column, still open: recomputed from its own samples each time.
  if (k_newest >= k_first && k_newest <= k_last) {
    bool have_previous = have_previous_;
    double previous_t = previous_t_;
    Run open;
    for (; i < n; ++i, ++last_scanned_) fold(series[i], max_gap, have_previous, previous_t, open, out);
    open.flush(out);
  }
}

}  // namespace telesphere::console::telemetry
