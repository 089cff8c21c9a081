// SPDX-License-Identifier: MIT
/// @brief The geometry of spherical rendering (paper §III-D, DESIGN.md §3) in double precision:
///        eye rays from XrFovf angles, the ray–sphere hit, the GL projection matrix of an eye,
///        and γ, the angular error of the constant-distance assumption.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "xr/render/eye_view.h"

namespace telesphere::xr::render {

/// γ(d, Δx, r) = atan2(d, Δx) − atan2(r, Δx) (paper eq. 4): the angle (rad) by which an object at
/// distance d (m) straight ahead of the camera appears displaced when the eye is translated by
/// Δx (m) perpendicular to that ray and the scene is assumed at distance r (m). Positive when
/// the object is beyond the sphere (d > r); 0 at d = r or Δx = 0 (d, r > 0: atan2(·, 0) = π/2
/// for both terms); tends to π/2 − atan2(r, Δx) as d → ∞. Domain: d, r ≥ 0, Δx ≥ 0, finite.
/// Evaluated as atan2(Δx·(d − r), Δx² + r·d), the same angle without the cancellation of the
/// two terms near π/2, so that γ ≈ Δx·(1/r − 1/d) keeps full relative precision as Δx → 0.
double constantDistanceAngularError(double d, double dx, double r);

/// Direction (not unit) of the ray through eye pixel (col, row) in the eye frame (OpenXR view
/// convention): (tan x, tan y, −1), where col, row are continuous pixel coordinates with the
/// origin at the centre of the top-left pixel, rows downwards (image order).
Eigen::Vector3d eyeRay(const Fov& fov, int width, int height, double col, double row);

/// Far root t ≥ 0 of |o + t·d| = r for unit d (o, d in the camera frame, r > 0), computed
/// without cancellation: t = s − b (b ≤ 0) or −c/(b + s) (b > 0) with b = o·d, c = |o|² − r²,
/// s = sqrt(b² − c). Inside the sphere (c < 0) this is the one hit ahead of the eye. Outside
/// (c > 0, the eye translated further than r) it is the far side of the sphere, i.e. the eye sees
/// the sphere's inside surface through the near side, continuous with the inside case as the
/// eye crosses the surface. Nothing when the ray misses the sphere or it lies behind the eye.
/// `c` is passed in so that callers compute |o|² − r² once.
std::optional<double> sphereFarHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double c);

/// OpenGL clip-from-eye matrix for an XrFovf frustum with near plane `near` (m) and the far plane
/// at infinity: NDC z = 1 + 2·near/z_eye ∈ [−1, 1) (GL's default depth range; farther = larger
/// depth). Column vectors, right-multiplied by eye-frame points (OpenXR view convention).
Eigen::Matrix4d clipFromEye(const Fov& fov, double near);

}  // namespace telesphere::xr::render
