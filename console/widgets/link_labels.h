// SPDX-License-Identifier: MIT
/// @brief The link's enums as the console's panels name them (one wording everywhere).
#pragma once

#include <QString>

#include "console/supervision/visual_mode_label.h"
#include "robot/link/proto_enums.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console {

/// The mode in force as the panels name it (console/supervision/visual_mode_label.h); "?" for
/// one this console does not know.
inline QString visualModeLabel(link::proto::VisualMode mode) {
  const auto known = link::fromProto(mode);
  if (!known) return "?";
  const std::string_view label = supervision::visualModeLabel(*known);
  return QString::fromUtf8(label.data(), static_cast<qsizetype>(label.size()));
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
