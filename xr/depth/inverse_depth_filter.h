// SPDX-License-Identifier: MIT
/// @brief Temporal filtering of the inverse-depth grid (#35): per tile, an exponential average in
///        inverse depth (where the proxies' error is linear) that snaps to a new value when it
///        jumps (an object moved in, a hole closed) and otherwise moves at most `max_rate` per
///        second, so that sweep noise does not make the operator's view swim. Unconfident tiles
///        (filled from neighbours) pull with a smaller weight. The renderer takes the newest
///        filtered grid; filtering never waits for anything.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "xr/render/depth_proxy.h"

namespace telesphere::xr::depth {

struct InverseDepthFilterOptions {
  double time_constant_s = 0.15;     ///< of the exponential average toward each new measurement
  /// A jump larger than this (1/m) is taken at once. 0.25 rather than 0.5: an object closing at
  /// 0.5 m/s swept at 10 Hz jumps 0.25–0.5 1/m a sweep inside 0.7 m and lagged 3× further with 0.5,
  /// while σ 8 sensor noise at rest never reached either (`telesphere-bench depth`, filter table).
  double snap_per_m = 0.25;
  double max_rate_per_m_s = 4.0;     ///< otherwise the value moves at most this fast (1/m per s)
  double unconfident_weight = 0.25;  ///< how much a filled-in tile pulls, against a matched one
};

class InverseDepthFilter {
 public:
  explicit InverseDepthFilter(InverseDepthFilterOptions options = {}) : options_(options) {}

  /// Takes one sweep's grid (and its per-tile confidence, 0 for filled tiles) measured at
  /// `t_ns`; returns the filtered grid. The first grid, a grid of another tiling, or a time that
  /// goes backwards restarts the filter from the measurement.
  const render::InverseDepthGrid& update(const render::InverseDepthGrid& measured, const std::vector<float>& confidence,
                                         std::int64_t t_ns);

  /// The filtered grid so far (nothing before the first update).
  const std::optional<render::InverseDepthGrid>& current() const { return state_; }
  /// Tiles that snapped in the last update.
  int snapped() const { return snapped_; }

 private:
  InverseDepthFilterOptions options_;
  std::optional<render::InverseDepthGrid> state_;
  std::int64_t last_ns_ = 0;
  int snapped_ = 0;
};

}  // namespace telesphere::xr::depth
