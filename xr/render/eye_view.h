// SPDX-License-Identifier: MIT
/// @brief What one eye render needs besides the camera: the eye's projection (OpenXR XrFovf
///        angles and the render-target size), the pose T_cam_eye, and the renderer settings
///        (mode, path, sphere radius, border colour). Plus the checks that keep NaN/inf and
///        malformed poses away from the GPU (STYLE.md §14).
///
/// Frames (DESIGN.md §2): the eye frame follows the OpenXR view convention (x right, y up,
/// −z forward); the camera frame is optical (x right, y down, z forward). T_cam_eye maps points
/// from the eye frame into the camera frame, so an eye looking along the camera's optical axis
/// with no roll has R_cam_eye = kR_optical_view.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "robot/link/visual_mode.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::xr::render {

/// The axis flip between an OpenXR view frame (x right, y up, −z forward) and the optical frame
/// with the same origin and viewing direction (x right, y down, z forward): p_optical =
/// kR_optical_view · p_view. Its own inverse.
inline const Eigen::Matrix3d kR_optical_view = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();

/// Field of view as OpenXR's XrFovf: angles (rad) of the left, right, up and down frustum edges
/// from the view axis, left and down usually negative. Each in (−π/2, π/2), left < right,
/// down < up. Asymmetric frusta are the norm in headsets.
struct Fov {
  double angle_left = -0.7;
  double angle_right = 0.7;
  double angle_up = 0.7;
  double angle_down = -0.7;
};

/// One eye to render: its projection and where it is relative to the camera.
struct EyeView {
  Fov fov;
  int width = 0;   ///< render-target width, px
  int height = 0;  ///< render-target height, px
  /// Eye pose in the camera frame at the image's capture time (DESIGN.md §2).
  Eigen::Isometry3d T_cam_eye = Eigen::Isometry3d(kR_optical_view);
};

/// Render paths, the speed/accuracy knob: exact per-fragment projection, a tessellated sphere
/// with per-vertex projection, or a direction→pixel look-up texture.
enum class RenderPath { kExact, kMesh, kLut };

std::string_view renderPathName(RenderPath path);  ///< "exact", "mesh", "lut"
std::optional<RenderPath> parseRenderPath(std::string_view name);

struct RenderSettings {
  /// The visual mode (robot/link/visual_mode.h). In the renderer: full6d puts the eye at its
  /// tracked pose, orientation3d at the sphere's centre (only R_cam_eye used), fixed ignores the
  /// tracked pose and uses T_cam_eye_fixed (head-locked).
  link::VisualMode mode = link::VisualMode::kFull6d;
  RenderPath path = RenderPath::kExact;
  /// Sphere radius r (m), finite and > 0: the distance the whole scene is assumed to be at (the
  /// fixed proxy, or one radius from depth: depth_proxy.h's centreWeightedRadius).
  double radius = 1.0;
  /// The grid proxy (#35): when set, each eye ray meets this inverse-depth grid around the
  /// camera (gridProxyHit: a march to the first crossing, kGridProxySteps refinements) instead of the sphere of `radius`. Exact and
  /// look-up-table paths only; shared, never copied (the renderer uploads it once per grid).
  std::shared_ptr<const InverseDepthGrid> depth_grid;
  /// The grid proxy takes the closest of four tiles that span more than this inverse depth (1/m)
  /// per degree of tile instead of interpolating (depth_proxy.h, kGridEdgeSlopePerMPerDeg);
  /// infinity: bilinear.
  double grid_edge_slope_per_m_per_deg = kGridEdgeSlopePerMPerDeg;
  /// Each eye ray marches along the grid proxy in steps that move its point by at most this many
  /// tiles as the camera sees it, then refines the first crossing (depth_proxy.h, gridProxyHit);
  /// infinity: no march, fixed-point steps from the ray's own direction.
  double grid_march_step_tiles = kGridMarchStepTiles;
  /// Colour (RGBA, 0..1) of eye pixels the camera did not see: outside the model's valid region,
  /// outside the image, or rays that miss the sphere when the eye is outside it.
  Eigen::Vector4f border_rgba{0.0f, 0.0f, 0.0f, 1.0f};
  /// The camera image's colour is multiplied by this (0…1; the border is not): the operator
  /// view dims a frame whose camera pose was not measured (OperatorView).
  float image_gain = 1.0f;
  /// The camera image's colour saturation (0: grey, 1: as captured; the border keeps its colour):
  /// the operator view shows an image too old to trust in grey (link_state_overlay.h).
  float image_saturation = 1.0f;
  /// The head-locked pose of mode fixed (default: eye at the camera, looking along its axis).
  Eigen::Isometry3d T_cam_eye_fixed = Eigen::Isometry3d(kR_optical_view);
  /// Mesh path tessellation: rings in θ from the optical axis and segments in azimuth.
  int mesh_rings = 96;
  int mesh_segments = 192;
  /// Look-up-table path: table size (texels per side).
  int lut_size = 1024;
};

/// Why `T` cannot be rendered (a NaN/inf entry, a rotation that is not orthonormal with
/// determinant +1 to 1e-6), or nothing when it is fine.
std::optional<std::string> checkPose(const Eigen::Isometry3d& T);

/// Why `view` cannot be rendered (size, angles, pose), or nothing.
std::optional<std::string> checkEyeView(const EyeView& view);

/// Why `settings` cannot be used (radius, border colour, fixed pose, tessellation), or nothing.
std::optional<std::string> checkRenderSettings(const RenderSettings& settings);

/// Mode, path, radius and how the grid proxy meets a depth edge ("nearest": the closest of the four
/// tiles above kGridEdgeSlopePerMPerDeg; "bilinear": interpolated everywhere) as a user gives them (command
/// lines, files), parsed and checked: the settings (other fields default), or nothing with the
/// reason in *error.
std::optional<RenderSettings> renderSettingsFromText(std::string_view mode, std::string_view path,
                                                     double radius, std::string* error,
                                                     std::string_view grid_edges = "nearest");
/// The command lines' help for that grid_edges text (telesphere-xr desktop, offscreen, openxr).
inline constexpr const char* kGridEdgesHelp =
    "how the grid proxy meets a depth edge: nearest (the tile whose centre is closest, so a near object keeps its "
    "outline where the depth's tiles put it) or bilinear (interpolated: the outline moves with the head)";

/// The pose the renderer actually uses for `mode`: T_cam_eye (full6d), its rotation only
/// (orientation3d), or T_cam_eye_fixed (fixed).
Eigen::Isometry3d effectiveT_cam_eye(const EyeView& view, const RenderSettings& settings);

}  // namespace telesphere::xr::render
