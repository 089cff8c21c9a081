// SPDX-License-Identifier: MIT
/// @brief What a depth proxy leaves of the operator's eye-image error (`telesphere-bench depth`,
///        #35): an eye away from the camera by 5 mm (at rest) or 6 cm (moving) in 10 directions;
///        each eye ray shows the scene point the camera sees through the proxy's point on that ray,
///        and the error is the angle from the eye ray to that point. Eye rays whose true point the
///        camera cannot see (disoccluded) are counted apart.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "robot/cameras/synthetic_scene.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::bench::depth_bench {

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline constexpr double kEyeHalfFovDeg = 45.0;  ///< a headset eye, square
inline constexpr double kFoveaDeg = 10.0;       ///< ± around the eye's forward axis
inline constexpr double kRestOffsetM = 0.005;
inline constexpr double kMovingOffsetM = 0.06;

struct ErrorSet {
  std::vector<double> whole, fovea;  // degrees
  std::vector<double> objects;       // the eye rays whose true point is on an object in the room (not the room itself)
};

struct Proxy {
  std::string name, label;
  double radius_m = 0;                               // the sphere proxies
  std::optional<xr::render::InverseDepthGrid> grid;  // the grid proxies
  ErrorSet rest, moving;
  double edge_slope_per_m_per_deg = xr::render::kGridEdgeSlopePerMPerDeg;  // the grid proxies: one tile at edges above this × tile
  xr::render::GridEdgeTile edge_tile = xr::render::GridEdgeTile::kClosest;  // which one
  double march_step_tiles = xr::render::kGridMarchStepTiles;              // the grid proxies' march (infinity: fixed-point steps)
  std::vector<int> lookups = {};                                           // the grid proxies: grid reads per moving eye ray
};

/// p50 and p90 of the whole field and of the fovea.
nlohmann::json stats(const ErrorSet& e);

/// The eye's offsets from the camera: 8 directions across the view and 2 along it.
std::vector<Eigen::Vector3d> offsetDirections();

/// Each proxy's eye-image errors at rest and moving (or moving only); the fraction of moving eye
/// rays whose true point the camera cannot see (left out of every proxy's errors).
double evaluateEyeErrors(const robot::cameras::SyntheticScene& scene, const robot::cameras::SceneView& camera,
                         std::vector<Proxy>& proxies, int rays, bool with_rest);

}  // namespace telesphere::bench::depth_bench
