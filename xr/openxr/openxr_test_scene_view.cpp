// SPDX-License-Identifier: MIT
/// @brief OpenXrTestSceneView: the test scene's camera on the GPU, the nominal pose, eye renders.
#include "xr/openxr/openxr_test_scene_view.h"

#include "robot/link/head_angles.h"
#include "xr/openxr/openxr_test_scene.h"

namespace telesphere::xr::openxr {

std::unique_ptr<OpenXrTestSceneView> OpenXrTestSceneView::create(const render::RenderSettings& settings, std::string* error) {
  auto camera = std::make_unique<render::GpuCamera>(OpenXrTestScene::camera(), OpenXrTestScene::kImageWidth,
                                            OpenXrTestScene::kImageHeight);
  if (!camera->upload(OpenXrTestScene::image(), error)) return nullptr;
  std::unique_ptr<OpenXrTestSceneView> view(new OpenXrTestSceneView(settings, std::move(camera)));
  if (!view->renderer_.prepare(*view->camera_, settings.path, error)) return nullptr;
  return view;
}

bool OpenXrTestSceneView::beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t, bool valid, std::string*) {
  // The nominal pose: the HMD pose of the session's first tracked frame, pitch and roll removed.
  if (valid && !T_vr_nom_) T_vr_nom_ = link::withoutPitchAndRoll(T_vr_hmd);
  return true;
}

std::optional<Eigen::Isometry3d> OpenXrTestSceneView::T_cam_eye(int, const Eigen::Isometry3d& T_vr_eye) const {
  if (!T_vr_nom_) return std::nullopt;
  return Eigen::Isometry3d(render::kR_optical_view) * T_vr_nom_->inverse() * T_vr_eye;
}

bool OpenXrTestSceneView::renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view,
                                    GLuint framebuffer, std::string* error) {
  const auto T = T_cam_eye(eye, T_vr_eye);
  if (!T) {
    *error = "the test scene has no nominal pose yet (no tracked head pose)";
    return false;
  }
  render::EyeView placed = view;
  placed.T_cam_eye = *T;
  return renderer_.render(*camera_, placed, settings_, framebuffer, error);
}

}  // namespace telesphere::xr::openxr
