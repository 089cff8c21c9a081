// SPDX-License-Identifier: MIT
/// @brief The CPU reference renderer.
#include "xr/render/reference_renderer.h"

#include <algorithm>
#include <cmath>

#include "xr/render/depth_proxy.h"
#include "xr/render/sphere_geometry.h"

namespace telesphere::xr::render {

namespace {

/// The grid proxy's parameters for `settings` (computed once per image: O(tiles)).
std::optional<GridProxyParams> gridParams(const RenderSettings& settings) {
  if (!settings.depth_grid) return std::nullopt;
  return gridProxyParams(*settings.depth_grid, settings.grid_edge_slope_per_m_per_deg, settings.grid_march_step_tiles);
}

std::optional<Eigen::Vector2d> cameraPixel(const calib::GenericCamera& camera, int image_width, int image_height,
                                           const EyeView& view, const RenderSettings& settings,
                                           const std::optional<GridProxyParams>& grid, double col, double row) {
  const Eigen::Isometry3d T_cam_eye = effectiveT_cam_eye(view, settings);
  const Eigen::Vector3d o = T_cam_eye.translation();
  const Eigen::Vector3d d =
      (T_cam_eye.linear() * eyeRay(view.fov, view.width, view.height, col, row)).normalized();
  const std::optional<Eigen::Vector3d> p =
      grid ? gridProxyHit(*settings.depth_grid, *grid, o, d) : sphereProxyHit(settings.radius, o, d);
  if (!p) return std::nullopt;
  Eigen::Vector2d px;
  if (!camera.project(*p, px)) return std::nullopt;
  if (!(px.x() >= -0.5 && px.y() >= -0.5 && px.x() <= image_width - 0.5 &&
        px.y() <= image_height - 0.5))
    return std::nullopt;
  return px;
}

}  // namespace

std::optional<Eigen::Vector2d> referenceCameraPixel(const calib::GenericCamera& camera,
                                                    int image_width, int image_height,
                                                    const EyeView& view,
                                                    const RenderSettings& settings, double col,
                                                    double row) {
  return cameraPixel(camera, image_width, image_height, view, settings, gridParams(settings), col, row);
}

std::optional<RgbaImage> renderReference(const calib::GenericCamera& camera,
                                         const SourceImage& image, const EyeView& view,
                                         const RenderSettings& settings) {
  if (checkEyeView(view) || checkRenderSettings(settings) || !image.consistent())
    return std::nullopt;
  RgbaImage out;
  out.width = view.width;
  out.height = view.height;
  out.rgba.resize(static_cast<std::size_t>(view.width) * view.height * 4);
  const Eigen::Vector4f border = settings.border_rgba;
  const std::optional<GridProxyParams> grid = gridParams(settings);
  for (int row = 0; row < view.height; ++row) {
    for (int col = 0; col < view.width; ++col) {
      const auto px = cameraPixel(camera, image.width, image.height, view, settings, grid, col, row);
      Eigen::Vector4f value = border;
      if (px) {
        value = image.sample(*px).cast<float>();
        // As the shaders: towards BT.601 luma by 1 − saturation, then the gain.
        const float luma = 0.299f * value[0] + 0.587f * value[1] + 0.114f * value[2];
        value.head<3>() = luma + settings.image_saturation * (value.head<3>().array() - luma);
        value.head<3>() *= settings.image_gain;
      }
      Eigen::Map<Eigen::Vector4f>(&out.rgba[(static_cast<std::size_t>(row) * view.width + col) * 4]) =
          value;
    }
  }
  return out;
}

std::ostream& operator<<(std::ostream& os, const ProjectionMapError& e) {
  return os << "max " << e.max_px << " px, p99.9 " << e.p999_px << " px, mean " << e.mean_px << " px over " << e.compared
            << " pixels, " << e.validity_mismatch << " of " << e.total << " differ in validity";
}

ProjectionMapError compareProjectionMap(const std::vector<float>& rgba,
                                        const calib::GenericCamera& camera,
                                        const SourceImage& coordinates, const EyeView& view,
                                        const RenderSettings& settings) {
  ProjectionMapError e;
  double sum = 0.0;
  std::vector<double> errors;
  const std::optional<GridProxyParams> grid = gridParams(settings);
  for (int row = 0; row < view.height; ++row)
    for (int col = 0; col < view.width; ++col) {
      const float* v = &rgba[(static_cast<std::size_t>(row) * view.width + col) * 4];
      const bool rendered_valid = v[3] > 0.5f;
      const auto ref = cameraPixel(camera, coordinates.width, coordinates.height, view, settings, grid, col, row);
      ++e.total;
      if (rendered_valid != bool(ref)) {
        ++e.validity_mismatch;
        continue;
      }
      if (!ref) continue;
      const Eigen::Vector4d expected = coordinates.sample(*ref);
      const double err = std::hypot(v[0] - expected[0], v[1] - expected[1]);
      e.max_px = std::max(e.max_px, err);
      errors.push_back(err);
      sum += err;
      ++e.compared;
    }
  e.mean_px = e.compared ? sum / e.compared : 0.0;
  if (!errors.empty()) {
    const auto nth = errors.begin() + static_cast<std::ptrdiff_t>(0.999 * static_cast<double>(errors.size() - 1));
    std::nth_element(errors.begin(), nth, errors.end());
    e.p999_px = *nth;
  }
  return e;
}

}  // namespace telesphere::xr::render
