// SPDX-License-Identifier: MIT
/// @brief The console's plotted series by name (DESIGN.md §7): each a TimeSeries on the console's
///        plot clock, all trimmed to one retention window so memory stays bounded however long the
///        console runs, plus a hard cap per series for a paused view. Qt-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "console/telemetry/time_series.h"

namespace telesphere::console::telemetry {

/// What a series is, for legends, axes and CSV headers.
struct SeriesInfo {
  std::string name;   ///< "latency.displayed", …
  std::string label;  ///< "uploaded → displayed"
  std::string unit;   ///< "ms", "cm/s", …
};

class SeriesStore {
 public:
  /// Samples kept per series at most, even while trimming is held back (a paused plot).
  static constexpr std::size_t kMaxSamplesPerSeries = 2'000'000;

  /// The series `info.name`, created on first use (later calls return the same one).
  TimeSeries& series(const SeriesInfo& info, double max_gap_s = 0.5);
  /// The series called `name`, or null.
  const TimeSeries* find(const std::string& name) const;
  const SeriesInfo* info(const std::string& name) const;

  /// Seconds of data kept behind the newest time (the longest plot window the user may pick).
  void setRetention(double seconds) { retention_s_ = seconds; }
  double retention() const { return retention_s_; }
  /// Drops samples older than now − retention, but none newer than `keep_from` (a paused view
  /// still shows what it showed); the hard cap applies regardless.
  void trim(double now, double keep_from);
  void clear();

  std::size_t totalSamples() const;
  std::size_t bytes() const;
  /// Incremented by every append through markChanged(): the plots redraw only when it moved.
  std::uint64_t version() const { return version_; }
  void markChanged() { ++version_; }

 private:
  struct Entry {
    SeriesInfo info;
    TimeSeries series;
  };
  std::map<std::string, Entry> entries_;
  double retention_s_ = 120.0;
  std::uint64_t version_ = 0;
};

}  // namespace telesphere::console::telemetry
