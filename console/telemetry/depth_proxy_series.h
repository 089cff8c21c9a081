// SPDX-License-Identifier: MIT
/// @brief The operator's scene proxy (#35, DESIGN.md §11) as plotted series, for the supervisor's
///        scene-depth graph. Qt-free.
///
/// From the XR app, per telemetry batch (XrTelemetry.depth, at the batch's time):
///   depth.radius_left_m, depth.radius_right_m   the radius each eye's sphere has: the session's r
///        with the fixed proxy, else the centre-weighted radius of that camera's stereo depth, m
///   depth.matched_left_pct, depth.matched_right_pct   the depth estimate's tiles matched of those
///        the camera sees (its confidence), % (no sample before the first estimate)
///   depth.age_ms   the estimate's pair: capture → the batch, ms
///   depth.sweep_ms CPU ms of the pair's sweeps and filters
#pragma once

#include <cstddef>
#include <optional>

#include "console/telemetry/series_store.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::telemetry {

namespace series {
inline constexpr const char* kDepthRadiusLeftM = "depth.radius_left_m";
inline constexpr const char* kDepthRadiusRightM = "depth.radius_right_m";
inline constexpr const char* kDepthMatchedLeftPct = "depth.matched_left_pct";
inline constexpr const char* kDepthMatchedRightPct = "depth.matched_right_pct";
inline constexpr const char* kDepthAgeMs = "depth.age_ms";
inline constexpr const char* kDepthSweepMs = "depth.sweep_ms";
}  // namespace series

class DepthProxySeries {
 public:
  /// Creates the six series (empty) in `store`.
  explicit DepthProxySeries(SeriesStore& store);

  /// One batch's state at `t` (plot clock, s); returns the samples appended.
  std::size_t add(const link::proto::DepthProxyState& state, double t);

  /// Label and unit of a depth.* series; nothing for another name.
  static std::optional<SeriesInfo> infoOf(const char* name);

 private:
  TimeSeries *radius_[2], *matched_[2], *age_, *sweep_;
};

}  // namespace telesphere::console::telemetry
