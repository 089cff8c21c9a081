// SPDX-License-Identifier: MIT
/// @brief The three visual modes of the paper's user study (§IV-B, DESIGN.md §3), one enum for
///        the robot's head controller, the XR app's renderer, the console and the link (proto
///        VisualMode, converted in robot/link/proto_enums.h only; this header needs no protobuf,
///        so the renderer does not either):
///          full6d         the head follows in 6D; the image on a sphere around each camera, the
///                         eye at its tracked position;
///          orientation3d  the head follows the orientation only (position held at the nominal
///                         pose); the eye at the sphere's centre, only its rotation used;
///          fixed          the head holds the nominal pose pitched 45° down; the image head-locked.
#pragma once

#include <optional>
#include <string_view>

namespace telesphere::link {

enum class VisualMode { kFull6d, kOrientation3d, kFixed };

/// "full6d", "orientation3d", "fixed": command lines, files, logs and study records.
inline std::string_view visualModeName(VisualMode mode) {
  switch (mode) {
    case VisualMode::kFull6d: return "full6d";
    case VisualMode::kOrientation3d: return "orientation3d";
    case VisualMode::kFixed: return "fixed";
  }
  return "?";
}

inline std::optional<VisualMode> parseVisualMode(std::string_view name) {
  for (VisualMode m : {VisualMode::kFull6d, VisualMode::kOrientation3d, VisualMode::kFixed})
    if (visualModeName(m) == name) return m;
  return std::nullopt;
}

/// The next mode in the operator's cycle full6d → orientation3d → fixed → full6d (the M key).
inline VisualMode nextVisualMode(VisualMode mode) {
  switch (mode) {
    case VisualMode::kFull6d: return VisualMode::kOrientation3d;
    case VisualMode::kOrientation3d: return VisualMode::kFixed;
    case VisualMode::kFixed: return VisualMode::kFull6d;
  }
  return VisualMode::kFull6d;
}

}  // namespace telesphere::link
