// SPDX-License-Identifier: MIT
/// @brief StereoViewRenderer: per-frame upload of both cameras' planes, per-eye render.
#include "xr/frame_loop/stereo_view_renderer.h"

#include <chrono>

#include "calib/camera_resolution.h"
#include "robot/link/link_endpoints.h"
#include "robot/link/link_pose.h"

namespace telesphere::xr::frame_loop {

StereoViewRenderer::StereoViewRenderer(const calib::SystemCalibration& calibration,
                                       const render::RenderSettings& settings, int upload_slots)
    : ring_(upload_slots), calibration_(calibration), settings_(settings) {}

StereoViewRenderer::~StereoViewRenderer() = default;

bool StereoViewRenderer::setCalibration(const calib::SystemCalibration& calibration, std::string* error) {
  if (calibration.cameras.size() != 2) {
    *error = "the calibration needs two cameras for a stereo view";
    return false;
  }
  calibration_ = calibration;
  for (auto& camera : cameras_) camera.reset();
  for (auto& coordinates : coordinates_) coordinates.reset();
  frame_.reset();
  return true;
}

bool StereoViewRenderer::setFrame(const std::shared_ptr<const video::DecodedStereoFrame>& frame,
                                  std::string* error) {
  ring_.reclaim();  // slots whose copies are done go back to the decoder
  // The same decoded frame object: already up. (Not compared by sequence number: a restarted
  // robot counts from 1 again.)
  if (!frame || frame == frame_) return true;
  if (calibration_.cameras.size() != 2) {
    *error = "the calibration needs two cameras for a stereo view";
    return false;
  }
  for (int i = 0; i < 2; ++i) {
    const auto& planes = i == 0 ? frame->left : frame->right;
    if (!planes) {
      *error = "frame " + std::to_string(frame->frame.sequence()) + " has no decoded image";
      return false;
    }
    if (!cameras_[i] || cameras_[i]->imageWidth() != planes->width ||
        cameras_[i]->imageHeight() != planes->height) {
      const auto scaled = calib::atResolution(calibration_.cameras[i], planes->width, planes->height, error);
      if (!scaled) return false;
      cameras_[i] = std::make_unique<render::GpuCamera>(scaled->camera, planes->width, planes->height);
      if (!renderer_.prepare(*cameras_[i], settings_.path, error)) return false;
    }
  }
  // The ring is made for the size the decoder delivers (the left camera's, should they differ):
  // from the next frame on, the decoder writes into it.
  if (ring_.source() && !ring_.prepare(frame->left->layout(), error))
    return false;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 2; ++i) {
    const render::YuvPlanes& planes = *(i == 0 ? frame->left : frame->right);
    if (!cameras_[i]->upload(render::SourceImage::yuv(i == 0 ? frame->left : frame->right), error)) return false;
    if (planes.slot) ring_.fenceCopy(*planes.slot);
  }
  last_upload_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  frame_ = frame;
  uploaded_ns_ = link::linkNowNs();
  return true;
}

bool StereoViewRenderer::renderEye(int eye, const Eigen::Isometry3d& T_robot_vr,
                                   const Eigen::Isometry3d& T_vr_eye, render::EyeView view,
                                   GLuint framebuffer, std::string* error) {
  if (eye < 0 || eye > 1) {
    *error = "eye must be 0 (left) or 1 (right)";
    return false;
  }
  if (!frame_ || !cameras_[eye]) {  // nothing received yet: the border colour only
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, view.width, view.height);
    const Eigen::Vector4f& c = settings_.border_rgba;
    glClearColor(c[0], c[1], c[2], c[3]);
    glClear(GL_COLOR_BUFFER_BIT);
    return true;
  }
  if (!placeEye(eye, T_robot_vr, T_vr_eye, &view, error)) return false;
  return renderer_.render(*cameras_[eye], view, settingsForEye(eye), framebuffer, error);
}

render::RenderSettings StereoViewRenderer::settingsForEye(int eye) const {
  render::RenderSettings settings = settings_;
  if (!depth_ || depth_proxy_ == link::DepthProxy::kFixed || eye < 0 || eye > 1) return settings;
  if (depth_proxy_ == link::DepthProxy::kGrid && settings.path != render::RenderPath::kMesh) {
    settings.depth_grid = depth_->grid[eye];
  } else {
    settings.radius = depth_->radius_m[eye];
  }
  return settings;
}

std::optional<Eigen::Isometry3d> StereoViewRenderer::cameraFromEye(int eye, const Eigen::Isometry3d& T_robot_vr,
                                                                   const Eigen::Isometry3d& T_vr_eye) const {
  if (!frame_ || eye < 0 || eye > 1) return std::nullopt;
  const auto& image = eye == 0 ? frame_->frame.left() : frame_->frame.right();
  return link::fromLinkPose(image.t_robot_cam()).inverse() * T_robot_vr * T_vr_eye;
}

bool StereoViewRenderer::placeEye(int eye, const Eigen::Isometry3d& T_robot_vr, const Eigen::Isometry3d& T_vr_eye,
                                  render::EyeView* view, std::string* error) const {
  view->T_cam_eye = *cameraFromEye(eye, T_robot_vr, T_vr_eye);
  if (const auto why = render::checkPose(view->T_cam_eye)) {
    *error = "eye pose: " + *why;
    return false;
  }
  return true;
}

bool StereoViewRenderer::renderProjectionMap(int eye, const Eigen::Isometry3d& T_robot_vr,
                                             const Eigen::Isometry3d& T_vr_eye, render::EyeView view,
                                             GLuint framebuffer, std::string* error) {
  if (eye < 0 || eye > 1 || !frame_ || !cameras_[eye]) {
    *error = "no camera frame to map yet";
    return false;
  }
  const render::GpuCamera& camera = *cameras_[eye];
  if (!coordinates_[eye] || coordinates_[eye]->imageWidth() != camera.imageWidth() ||
      coordinates_[eye]->imageHeight() != camera.imageHeight()) {
    coordinates_[eye] = std::make_unique<render::GpuCamera>(camera.camera(), camera.imageWidth(), camera.imageHeight());
    if (!coordinates_[eye]->upload(render::SourceImage::pixelCoordinates(camera.imageWidth(), camera.imageHeight()), error))
      return false;
  }
  if (!placeEye(eye, T_robot_vr, T_vr_eye, &view, error)) return false;
  render::RenderSettings settings = settingsForEye(eye);
  settings.border_rgba.setZero();  // alpha 0: no camera pixel
  settings.image_gain = 1.0f;      // coordinates, not colours
  settings.image_saturation = 1.0f;
  return renderer_.render(*coordinates_[eye], view, settings, framebuffer, error);
}

}  // namespace telesphere::xr::frame_loop
