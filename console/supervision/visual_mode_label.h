// SPDX-License-Identifier: MIT
/// @brief The three visual modes (robot/link/visual_mode.h) in the console's words, written once
///        for every panel, table, questionnaire and the study report's figures: "full 6D",
///        "3D orientation", "fixed perspective"; short ("6D", "3D", "fixed") where a column must
///        fit; as a title ("Full 6D", "Fixed perspective") at the start of a figure's label.
///        Qt-free; the widgets wrap them in QString.
#pragma once

#include <cctype>
#include <string>
#include <string_view>

#include "robot/link/visual_mode.h"

namespace telesphere::console::supervision {

/// "full 6D", "3D orientation", "fixed perspective".
inline std::string_view visualModeLabel(link::VisualMode mode) {
  switch (mode) {
    case link::VisualMode::kFull6d: return "full 6D";
    case link::VisualMode::kOrientation3d: return "3D orientation";
    case link::VisualMode::kFixed: return "fixed perspective";
  }
  return "?";
}

/// "6D", "3D", "fixed": where a column must fit beside others.
inline std::string_view visualModeShortLabel(link::VisualMode mode) {
  switch (mode) {
    case link::VisualMode::kFull6d: return "6D";
    case link::VisualMode::kOrientation3d: return "3D";
    case link::VisualMode::kFixed: return "fixed";
  }
  return "?";
}

/// The label of a mode's name ("full6d" → "full 6D", as study records and files name modes);
/// `unknown` for a name that is not one of the three.
inline std::string visualModeLabel(std::string_view name, std::string_view unknown) {
  const auto mode = link::parseVisualMode(name);
  return std::string(mode ? visualModeLabel(*mode) : unknown);
}

/// The label with a capital first letter ("Full 6D", "3D orientation", "Fixed perspective");
/// `unknown` for a name that is not one of the three.
inline std::string visualModeTitle(std::string_view name, std::string_view unknown) {
  const auto mode = link::parseVisualMode(name);
  if (!mode) return std::string(unknown);
  std::string title(visualModeLabel(*mode));
  title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
  return title;
}

}  // namespace telesphere::console::supervision
