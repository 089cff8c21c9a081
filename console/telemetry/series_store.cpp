// SPDX-License-Identifier: MIT
/// @brief SeriesStore: named series, one retention window.
#include "console/telemetry/series_store.h"

#include <algorithm>

namespace telesphere::console::telemetry {

TimeSeries& SeriesStore::series(const SeriesInfo& info, double max_gap_s) {
  auto it = entries_.find(info.name);
  if (it == entries_.end()) it = entries_.emplace(info.name, Entry{info, TimeSeries(max_gap_s)}).first;
  return it->second.series;
}

const TimeSeries* SeriesStore::find(const std::string& name) const {
  const auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second.series;
}

const SeriesInfo* SeriesStore::info(const std::string& name) const {
  const auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second.info;
}

void SeriesStore::trim(double now, double keep_from) {
  const double cut = std::min(now - retention_s_, keep_from);
  for (auto& [name, entry] : entries_) {
    entry.series.trimBefore(cut);
    entry.series.keepNewest(kMaxSamplesPerSeries);
  }
}

void SeriesStore::clear() {
  for (auto& [name, entry] : entries_) entry.series.clear();
  ++version_;
}

std::size_t SeriesStore::totalSamples() const {
  std::size_t n = 0;
  for (const auto& [name, entry] : entries_) n += entry.series.size();
  return n;
}

std::size_t SeriesStore::bytes() const {
  std::size_t n = 0;
  for (const auto& [name, entry] : entries_) n += entry.series.bytes();
  return n;
}

}  // namespace telesphere::console::telemetry
