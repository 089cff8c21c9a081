// SPDX-License-Identifier: MIT
/// @brief evaluateNominalGate: freshness and stillness of the operator's head.
#include "console/supervision/nominal_pose_gate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace telesphere::console::supervision {

NominalGateStatus evaluateNominalGate(const std::deque<telemetry::HeadPoseSample>& poses, double now_s,
                                      const NominalGateOptions& options) {
  NominalGateStatus s;
  if (poses.empty()) {
    s.reason = "no head pose from the XR app (is telesphere-xr running, the headset on?)";
    return s;
  }
  const telemetry::HeadPoseSample& newest = poses.back();
  s.age_s = now_s - newest.t;
  s.angles = link::headAnglesOf(newest.T_vr_hmd);
  s.fresh = s.age_s <= options.max_age_s;
  int in_window = 0;
  const Eigen::Quaterniond q_newest(newest.T_vr_hmd.linear());
  for (auto it = poses.rbegin(); it != poses.rend() && newest.t - it->t <= options.still_window_s; ++it) {
    ++in_window;
    const double turn = q_newest.angularDistance(Eigen::Quaterniond(it->T_vr_hmd.linear())) * 180.0 / M_PI;
    s.turn_deg = std::max(s.turn_deg, turn);
    s.move_m = std::max(s.move_m, (it->T_vr_hmd.translation() - newest.T_vr_hmd.translation()).norm());
  }
  s.still = in_window >= options.min_poses && s.turn_deg < options.max_turn_deg && s.move_m < options.max_move_m;
  s.can_capture = s.fresh && s.still;
  char text[160];
  if (!s.fresh) {
    std::snprintf(text, sizeof(text), "head poses are stale (newest %.2f s old)", s.age_s);
    s.reason = text;
  } else if (in_window < options.min_poses) {
    s.reason = "too few head poses to judge stillness";
  } else if (!s.still) {
    std::snprintf(text, sizeof(text), "the head is moving (%.1f° / %.1f cm in %.1f s): hold still", s.turn_deg,
                  s.move_m * 100.0, options.still_window_s);
    s.reason = text;
  }
  return s;
}

}  // namespace telesphere::console::supervision
