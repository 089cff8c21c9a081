// SPDX-License-Identifier: MIT
/// @brief The calibration wizard's sample gates (see sample_gates.h).
#include "calib/sample_gates.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>

namespace telesphere::calib {
namespace {

std::vector<double> sharedDisplacements(const TargetObservation& a, const TargetObservation& b) {
  std::unordered_map<int, std::size_t> index;
  for (std::size_t i = 0; i < b.corner_ids.size(); ++i) index[b.corner_ids[i]] = i;
  std::vector<double> d;
  for (std::size_t i = 0; i < a.corner_ids.size(); ++i)
    if (const auto it = index.find(a.corner_ids[i]); it != index.end())
      d.push_back((a.corners_px[i] - b.corners_px[it->second]).norm());
  return d;
}

std::string format(const char* fmt, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

}  // namespace

double medianCornerMotion(const TargetObservation& a, const TargetObservation& b, int min_shared) {
  std::vector<double> d = sharedDisplacements(a, b);
  if (d.empty() || static_cast<int>(d.size()) < min_shared) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = d.begin() + std::ptrdiff_t(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  if (d.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(d.begin(), mid));
}

double meanCornerDisplacement(const TargetObservation& a, const TargetObservation& b, int min_shared) {
  const std::vector<double> d = sharedDisplacements(a, b);
  if (d.empty() || static_cast<int>(d.size()) < min_shared) return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (double v : d) sum += v;
  return sum / double(d.size());
}

GateResult judgeView(const TargetObservation& view, const TargetObservation* previous,
                     const std::vector<TargetObservation>& kept, const SampleGateOptions& options) {
  GateResult r;
  r.corners = static_cast<int>(view.corner_ids.size());
  r.motion_px = previous ? medianCornerMotion(view, *previous, options.min_shared_corners)
                         : std::numeric_limits<double>::quiet_NaN();
  r.novelty_px = std::numeric_limits<double>::infinity();
  for (const TargetObservation& k : kept)
    r.novelty_px = std::min(r.novelty_px, meanCornerDisplacement(view, k, options.min_shared_corners));
  if (r.corners < options.min_corners) {
    r.verdict = GateVerdict::kTooFewCorners;
    r.reason = format("%.0f corners (%.0f needed)", r.corners, options.min_corners);
  } else if (!previous) {
    r.verdict = GateVerdict::kNoPreviousView;
    r.reason = "no still before this one to tell whether the target is still";
  } else if (!(r.motion_px <= options.still_max_px)) {  // NaN (nothing shared) counts as moving
    r.verdict = GateVerdict::kMoving;
    r.reason = std::isnan(r.motion_px) ? "moving: the still before shares too few corners"
                                       : format("moving: %.2f px since the still before (%.2f allowed)", r.motion_px,
                                                options.still_max_px);
  } else if (r.novelty_px < options.min_novelty_px) {
    r.verdict = GateVerdict::kTooSimilar;
    r.reason = format("too similar: %.1f px from a kept view (%.1f needed)", r.novelty_px, options.min_novelty_px);
  } else {
    r.reason = "keep";
  }
  return r;
}

}  // namespace telesphere::calib
