// SPDX-License-Identifier: MIT
/// @brief Spherical-rendering geometry in double precision.
#include "xr/render/sphere_geometry.h"

#include <cmath>

namespace telesphere::xr::render {

double constantDistanceAngularError(double d, double dx, double r) {
  // atan2(d, Δx) − atan2(r, Δx) is the angle from (Δx, r) to (Δx, d); as one atan2 of their
  // cross and dot products it keeps full relative precision as Δx → 0, where the two terms of
  // eq. 4 both approach π/2 and their difference cancels.
  return std::atan2(dx * (d - r), dx * dx + r * d);
}

Eigen::Vector3d eyeRay(const Fov& fov, int width, int height, double col, double row) {
  const double fx = (col + 0.5) / width;         // 0 at the left edge, 1 at the right
  const double fy = 1.0 - (row + 0.5) / height;  // 0 at the bottom edge, 1 at the top
  const double tl = std::tan(fov.angle_left), tr = std::tan(fov.angle_right);
  const double td = std::tan(fov.angle_down), tu = std::tan(fov.angle_up);
  return {tl + fx * (tr - tl), td + fy * (tu - td), -1.0};
}

std::optional<double> sphereFarHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double c) {
  const double b = o.dot(d);
  const double disc = b * b - c;
  if (!(disc >= 0.0)) return std::nullopt;
  const double s = std::sqrt(disc);
  const double t = b <= 0.0 ? s - b : -c / (b + s);
  if (!(t >= 0.0)) return std::nullopt;
  return t;
}

Eigen::Matrix4d clipFromEye(const Fov& fov, double near) {
  const double l = std::tan(fov.angle_left), r = std::tan(fov.angle_right);
  const double d = std::tan(fov.angle_down), u = std::tan(fov.angle_up);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2.0 / (r - l);
  P(0, 2) = (r + l) / (r - l);
  P(1, 1) = 2.0 / (u - d);
  P(1, 2) = (u + d) / (u - d);
  P(2, 2) = -1.0;
  P(2, 3) = -2.0 * near;
  P(3, 2) = -1.0;
  return P;
}

}  // namespace telesphere::xr::render
