// SPDX-License-Identifier: MIT
/// @brief Names and checks of eye views and render settings.
#include "xr/render/eye_view.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace telesphere::xr::render {

std::string_view renderPathName(RenderPath path) {
  switch (path) {
    case RenderPath::kExact: return "exact";
    case RenderPath::kMesh: return "mesh";
    case RenderPath::kLut: return "lut";
  }
  return "?";
}

std::optional<RenderPath> parseRenderPath(std::string_view name) {
  for (RenderPath p : {RenderPath::kExact, RenderPath::kMesh, RenderPath::kLut})
    if (renderPathName(p) == name) return p;
  return std::nullopt;
}

std::optional<std::string> checkPose(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) {
    std::ostringstream os;
    os << "pose has a NaN or infinite entry:\n" << T.matrix();
    return os.str();
  }
  const Eigen::Matrix3d R = T.linear();
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(orthogonality < 1e-6) || !(R.determinant() > 0.0)) {
    std::ostringstream os;
    os << "pose rotation is not a rotation (|RᵀR − I|max = " << orthogonality
       << ", det = " << R.determinant() << ")";
    return os.str();
  }
  return std::nullopt;
}

std::optional<std::string> checkEyeView(const EyeView& view) {
  if (view.width <= 0 || view.height <= 0) {
    std::ostringstream os;
    os << "eye render size " << view.width << "x" << view.height << " is empty";
    return os.str();
  }
  const Fov& f = view.fov;
  constexpr double kHalfPi = 1.5707963267948966;
  const auto inside = [&](double a) { return std::isfinite(a) && std::abs(a) < kHalfPi; };
  if (!(inside(f.angle_left) && inside(f.angle_right) && inside(f.angle_up) &&
        inside(f.angle_down) && f.angle_left < f.angle_right && f.angle_down < f.angle_up)) {
    std::ostringstream os;
    os << "field of view (left " << f.angle_left << ", right " << f.angle_right << ", up "
       << f.angle_up << ", down " << f.angle_down
       << ") must have angles in (−π/2, π/2) with left < right and down < up";
    return os.str();
  }
  if (auto e = checkPose(view.T_cam_eye)) return "T_cam_eye: " + *e;
  return std::nullopt;
}

std::optional<std::string> checkRenderSettings(const RenderSettings& s) {
  if (!(std::isfinite(s.radius) && s.radius > 0.0)) {
    std::ostringstream os;
    os << "sphere radius " << s.radius << " must be finite and > 0";
    return os.str();
  }
  if (!s.border_rgba.allFinite()) return "border colour has a NaN or infinite component";
  if (!(s.image_gain >= 0.0f && s.image_gain <= 1.0f)) return "image gain must be within [0, 1]";
  if (!(s.image_saturation >= 0.0f && s.image_saturation <= 1.0f)) return "image saturation must be within [0, 1]";
  if (auto e = checkPose(s.T_cam_eye_fixed)) return "T_cam_eye_fixed: " + *e;
  if (s.mesh_rings < 2 || s.mesh_segments < 3 || s.mesh_rings > 4096 || s.mesh_segments > 8192)
    return "mesh tessellation must have 2..4096 rings and 3..8192 segments";
  if (s.lut_size < 2 || s.lut_size > 8192) return "look-up table size must be 2..8192";
  if (!(s.grid_edge_slope_per_m_per_deg >= 0.0))
    return "the grid's edge slope must be >= 0 (infinity: interpolated everywhere)";
  if (!(s.grid_march_step_tiles > 0.0))
    return "the grid's march step must be > 0 tiles (infinity: no march)";
  if (s.depth_grid && s.path == RenderPath::kMesh)
    return "the depth grid proxy needs the exact or look-up-table path (the mesh is a sphere)";
  return std::nullopt;
}

Eigen::Isometry3d effectiveT_cam_eye(const EyeView& view, const RenderSettings& settings) {
  switch (settings.mode) {
    case link::VisualMode::kFull6d: return view.T_cam_eye;
    case link::VisualMode::kOrientation3d: {
      Eigen::Isometry3d T = view.T_cam_eye;
      T.translation().setZero();
      return T;
    }
    case link::VisualMode::kFixed: return settings.T_cam_eye_fixed;
  }
  return view.T_cam_eye;
}

std::optional<RenderSettings> renderSettingsFromText(std::string_view mode, std::string_view path,
                                                     double radius, std::string* error, std::string_view grid_edges) {
  RenderSettings settings;
  const auto m = link::parseVisualMode(mode);
  const auto p = parseRenderPath(path);
  if (!m) {
    *error = "render mode must be full6d, orientation3d or fixed, got \"" + std::string(mode) + "\"";
    return std::nullopt;
  }
  if (!p) {
    *error = "render path must be exact, mesh or lut, got \"" + std::string(path) + "\"";
    return std::nullopt;
  }
  if (grid_edges != "nearest" && grid_edges != "bilinear") {
    *error = "grid edges must be nearest or bilinear, got \"" + std::string(grid_edges) + "\"";
    return std::nullopt;
  }
  settings.mode = *m;
  settings.path = *p;
  settings.radius = radius;
  settings.grid_edge_slope_per_m_per_deg =
      grid_edges == "nearest" ? kGridEdgeSlopePerMPerDeg : std::numeric_limits<double>::infinity();
  if (auto why = checkRenderSettings(settings)) {
    *error = *why;
    return std::nullopt;
  }
  return settings;
}

}  // namespace telesphere::xr::render
