// SPDX-License-Identifier: MIT
/// @brief The console's gate for capturing the nominal pose (DESIGN.md §2, issue: capture only
///        when fresh head poses arrive and the head is still). Qt-free; fed the operator's head
///        poses as the XR app reported them, at their own times.
///
/// Fresh: the newest pose is at most max_age_s old (plot clock). Still: over the last
/// still_window_s, the head turned less than max_turn_deg from the newest orientation and moved
/// less than max_move_m from the newest position, with at least min_poses poses in the window.
#pragma once

#include <deque>
#include <optional>
#include <string>

#include "console/telemetry/telemetry_model.h"
#include "robot/link/head_angles.h"

namespace telesphere::console::supervision {

struct NominalGateOptions {
  double max_age_s = 0.25;
  double still_window_s = 0.5;
  double max_turn_deg = 1.0;
  double max_move_m = 0.01;
  int min_poses = 5;
};

struct NominalGateStatus {
  bool fresh = false;
  bool still = false;
  bool can_capture = false;
  double age_s = -1.0;        ///< of the newest pose (−1: none)
  double turn_deg = 0.0;      ///< largest turn in the window
  double move_m = 0.0;        ///< largest move in the window
  std::optional<link::HeadAngles> angles;  ///< of the newest pose
  std::string reason;         ///< why not, in words ("" when can_capture)
};

NominalGateStatus evaluateNominalGate(const std::deque<telemetry::HeadPoseSample>& poses, double now_s,
                                      const NominalGateOptions& options = {});

}  // namespace telesphere::console::supervision
