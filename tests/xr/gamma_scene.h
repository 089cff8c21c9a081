// SPDX-License-Identifier: MIT
/// @brief The measured check of γ (paper eq. 4): a plane at distance d in front of the camera,
///        imaged through the camera model into a float image whose texels hold the plane point
///        (X, Y) they see; an eye translated by Δx perpendicular to the optical axis looks at the
///        sphere point straight ahead of the camera. The renderer's centre pixel then shows the
///        plane point that the camera sees there, and the angle between it and the eye's ray is
///        the renderer's angular error, to be compared with γ(d, Δx, r).
#pragma once

#include <cmath>

#include "calib/generic_camera.h"
#include "tests/xr/render_fixtures.h"
#include "xr/render/eye_view.h"
#include "xr/render/source_image.h"

namespace telesphere::test {

/// The camera image of the plane z = d (camera frame): RG = the plane point (X, Y) each pixel
/// sees (0 where it sees no point of the plane).
inline xr::render::SourceImage planeImage(const calib::GenericCamera& camera, int w, int h, double d) {
  std::vector<float> data(static_cast<std::size_t>(w) * h * 2, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Eigen::Vector3d ray;
      if (!camera.unproject(Eigen::Vector2d(x, y), ray) || !(ray.z() > 1e-6)) continue;
      const std::size_t i = (static_cast<std::size_t>(y) * w + x) * 2;
      data[i] = float(d * ray.x() / ray.z());
      data[i + 1] = float(d * ray.y() / ray.z());
    }
  return xr::render::SourceImage::floatImage(w, h, 2, std::move(data));
}

/// An odd-sized eye at (Δx, 0, 0) whose centre ray points at the sphere point (0, 0, r).
inline xr::render::EyeView gammaEye(double dx, double r) {
  xr::render::EyeView view;
  view.fov = {-0.2, 0.2, 0.2, -0.2};
  view.width = 21;
  view.height = 21;
  view.T_cam_eye = eyePose({dx, 0, 0}, rotation(std::atan2(-dx, r), {0, 1, 0}));
  return view;
}

/// The renderer's angular error at the centre pixel, signed like γ: the elevation of the shown
/// plane point (X, Y, d) over the −x axis as seen from the eye, minus that of the eye's ray.
inline double measuredGamma(float shown_x, float shown_y, double d, double dx, double r) {
  const Eigen::Vector3d to_shown = Eigen::Vector3d(shown_x, shown_y, d) - Eigen::Vector3d(dx, 0, 0);
  const double shown = std::atan2(to_shown.z(), -to_shown.x());
  const double ray = std::atan2(r, dx);
  return shown - ray;
}

}  // namespace telesphere::test
