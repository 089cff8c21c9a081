// SPDX-License-Identifier: MIT
/// @brief The sphere radius r the link accepts (paper §III-C, DESIGN.md §3), defined once: the
///        robot refuses any other (set_sphere_radius), the XR app follows only an accepted one
///        from the robot state and keeps its keys' steps inside, the console's editor offers
///        exactly this range.
#pragma once

#include <cmath>

namespace telesphere::link {

inline constexpr double kMinSphereRadius = 0.05;   ///< m
inline constexpr double kMaxSphereRadius = 1000.0;  ///< m

inline bool acceptedSphereRadius(double radius_m) {
  return std::isfinite(radius_m) && radius_m >= kMinSphereRadius && radius_m <= kMaxSphereRadius;
}

}  // namespace telesphere::link
