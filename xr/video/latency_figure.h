// SPDX-License-Identifier: MIT
/// @brief Median and 99th percentile of latency samples: the one way the operator side (decoder
///        statistics, the offscreen loop, benchmarks) summarises a latency.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace telesphere::xr::video {

/// Median and 99th percentile (ms); n = 0 when there were no samples.
struct LatencyFigure {
  double p50_ms = 0;
  double p99_ms = 0;
  std::size_t n = 0;
};

/// Nearest-rank percentiles of `samples_ms` (taken by value: reordered in place).
inline LatencyFigure latencyFigure(std::vector<double> samples_ms) {
  LatencyFigure f;
  f.n = samples_ms.size();
  if (samples_ms.empty()) return f;
  const auto at = [&](double q) {
    const auto k = static_cast<std::size_t>(q * static_cast<double>(samples_ms.size() - 1) + 0.5);
    std::nth_element(samples_ms.begin(), samples_ms.begin() + static_cast<std::ptrdiff_t>(k), samples_ms.end());
    return samples_ms[k];
  };
  f.p50_ms = at(0.5);
  f.p99_ms = at(0.99);
  return f;
}

}  // namespace telesphere::xr::video
