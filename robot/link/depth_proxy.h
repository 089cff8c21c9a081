// SPDX-License-Identifier: MIT
/// @brief The scene proxy the operator's renderer projects the camera images onto (#35, DESIGN.md
///        §11), one enum for the XR app's renderer, the robot (which holds the session's choice),
///        the console and the link (proto DepthProxyProto, converted in robot/link/proto_enums.h
///        only; this header needs no protobuf):
///          fixed   the sphere of the session's radius r around each camera (the paper's method);
///          radius  one sphere whose radius follows the scene: 1 / the centre-weighted median of
///                  the inverse depth the XR app's stereo sweep measures;
///          grid    a coarse inverse-depth grid per camera from the same sweep, each eye ray
///                  intersected with it.
#pragma once

#include <optional>
#include <string_view>

namespace telesphere::link {

enum class DepthProxy { kFixed, kRadius, kGrid };

/// "fixed", "radius", "grid": command lines, logs, stats.json, the console.
inline std::string_view depthProxyName(DepthProxy proxy) {
  switch (proxy) {
    case DepthProxy::kFixed: return "fixed";
    case DepthProxy::kRadius: return "radius";
    case DepthProxy::kGrid: return "grid";
  }
  return "?";
}

inline std::optional<DepthProxy> parseDepthProxy(std::string_view name) {
  for (DepthProxy p : {DepthProxy::kFixed, DepthProxy::kRadius, DepthProxy::kGrid})
    if (depthProxyName(p) == name) return p;
  return std::nullopt;
}

/// The next proxy in the operator's cycle fixed → radius → grid → fixed (the P key).
inline DepthProxy nextDepthProxy(DepthProxy proxy) {
  switch (proxy) {
    case DepthProxy::kFixed: return DepthProxy::kRadius;
    case DepthProxy::kRadius: return DepthProxy::kGrid;
    case DepthProxy::kGrid: return DepthProxy::kFixed;
  }
  return DepthProxy::kFixed;
}

}  // namespace telesphere::link
