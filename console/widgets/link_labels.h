// SPDX-License-Identifier: MIT
/// @brief The link's enums as the console's panels name them (one wording everywhere).
#pragma once

#include <QString>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console {

inline QString visualModeLabel(link::proto::VisualMode mode) {
  switch (mode) {
    case link::proto::VISUAL_MODE_FULL6D: return "full 6D";
    case link::proto::VISUAL_MODE_ORIENTATION3D: return "3D orientation";
    case link::proto::VISUAL_MODE_FIXED: return "fixed perspective";
    default: return "?";
  }
}

inline QString nominalStepLabel(link::proto::NominalStep step) {
  switch (step) {
    case link::proto::NOMINAL_STEP_FOLLOWING: return "following the operator";
    case link::proto::NOMINAL_STEP_HOLDING: return "holding the nominal pose";
    case link::proto::NOMINAL_STEP_CAPTURED: return "nominal pose captured, to confirm";
    default: return "?";
  }
}

}  // namespace telesphere::console
