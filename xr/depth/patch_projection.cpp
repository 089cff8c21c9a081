// SPDX-License-Identifier: MIT
/// @brief projectPatch: every sample, or the four corners and bilinear between them.
#include "xr/depth/patch_projection.h"

#include <cassert>

namespace telesphere::xr::depth {

bool projectPatch(const calib::GenericCamera& camera, const Eigen::Vector3f* directions, int n,
                  const Eigen::Isometry3d& T_view_reference, double rho, bool corners_only, Eigen::Vector2d* px_out) {
  assert(n >= 1 && directions && px_out);
  const Eigen::Matrix3d R = T_view_reference.linear();
  const Eigen::Vector3d t = T_view_reference.translation();
  // The point at depth 1/ρ along d, in the view's frame, up to its positive scale 1/ρ.
  const auto project = [&](int s, Eigen::Vector2d& px) { return camera.project(R * directions[s].cast<double>() + rho * t, px); };
  if (!corners_only || n < 3) {
    for (int s = 0; s < n * n; ++s)
      if (!project(s, px_out[s])) return false;
    return true;
  }
  Eigen::Vector2d p00, p01, p10, p11;  // rows 0 and n − 1, columns 0 and n − 1
  if (!project(0, p00) || !project(n - 1, p01) || !project((n - 1) * n, p10) || !project(n * n - 1, p11)) return false;
  for (int i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / (n - 1);
    for (int j = 0; j < n; ++j) {
      const double v = static_cast<double>(j) / (n - 1);
      px_out[i * n + j] = (1 - u) * ((1 - v) * p00 + v * p01) + u * ((1 - v) * p10 + v * p11);
    }
  }
  return true;
}

}  // namespace telesphere::xr::depth
