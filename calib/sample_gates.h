// SPDX-License-Identifier: MIT
/// @brief Whether a live view of the calibration target is worth keeping (issue #15's wizard
///        gates, paper §III-B): enough corners, the target still (the same corners in the still
///        taken just before moved less than a bound: no motion blur, no rolling shutter skew),
///        and a view that differs enough from every view already kept (mean displacement of the
///        corners both views share). Each verdict says why, with its number.
#pragma once

#include <string>
#include <vector>

#include "calib/target_detection.h"

namespace telesphere::calib {

struct SampleGateOptions {
  int min_corners = 24;          ///< of the target's corners, in this view
  double still_max_px = 0.5;     ///< median corner motion against the still before
  double min_novelty_px = 20.0;  ///< mean corner displacement against the closest kept view
  int min_shared_corners = 4;    ///< fewer shared corners than this: a different view
};

enum class GateVerdict { kKeep, kTooFewCorners, kNoPreviousView, kMoving, kTooSimilar };

struct GateResult {
  GateVerdict verdict = GateVerdict::kKeep;
  int corners = 0;
  double motion_px = 0;   ///< median corner motion against the previous still (NaN: none)
  double novelty_px = 0;  ///< against the closest kept view (+inf: nothing kept or nothing shared)
  std::string reason;     ///< "keep", "12 corners (24 needed)", "moving: 3.1 px since the last still (0.5 allowed)", …
  bool keep() const { return verdict == GateVerdict::kKeep; }
};

/// Median displacement of the corners `a` and `b` share (NaN when fewer than `min_shared`).
double medianCornerMotion(const TargetObservation& a, const TargetObservation& b, int min_shared);
/// Mean displacement of the corners `a` and `b` share (+inf when fewer than `min_shared`).
double meanCornerDisplacement(const TargetObservation& a, const TargetObservation& b, int min_shared);

/// The gates for `view`, given the same camera's still just before it (null: none) and the
/// views kept so far.
GateResult judgeView(const TargetObservation& view, const TargetObservation* previous,
                     const std::vector<TargetObservation>& kept, const SampleGateOptions& options = {});

}  // namespace telesphere::calib
