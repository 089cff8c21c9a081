// SPDX-License-Identifier: MIT
/// @brief The headset's test scene (OpenXrTestScene: one fisheye looking at a checkerboard) as
///        something the operator loop draws instead of the robot's frames: no robot needed. The
///        nominal pose is the head pose of the first frame, pitch and roll removed (see
///        openxr_test_scene.h); restart() forgets it (a new headset session).
#pragma once

#include <memory>
#include <optional>

#include "xr/frame_loop/operator_loop.h"
#include "xr/render/gpu_camera.h"
#include "xr/render/spherical_renderer.h"

namespace telesphere::xr::openxr {

class OpenXrTestSceneView final : public frame_loop::OperatorScene {
 public:
  /// Uploads the scene (needs a current GL context); nothing, with the reason, when GL fails.
  static std::unique_ptr<OpenXrTestSceneView> create(const render::RenderSettings& settings, std::string* error);

  bool beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display_ns, bool valid,
                  std::string* error) override;
  bool renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view, GLuint framebuffer,
                 std::string* error) override;
  void endFrame(std::int64_t, double, std::uint64_t) override {}
  std::optional<Eigen::Isometry3d> T_cam_eye(int eye, const Eigen::Isometry3d& T_vr_eye) const override;

  /// The next frame's head pose becomes the nominal pose again.
  void restart() { T_vr_nom_.reset(); }
  const render::RenderSettings& settings() const { return settings_; }

 private:
  OpenXrTestSceneView(const render::RenderSettings& settings, std::unique_ptr<render::GpuCamera> camera)
      : settings_(settings), camera_(std::move(camera)) {}
  render::RenderSettings settings_;
  std::unique_ptr<render::GpuCamera> camera_;
  render::SphericalRenderer renderer_;
  std::optional<Eigen::Isometry3d> T_vr_nom_;
};

}  // namespace telesphere::xr::openxr
