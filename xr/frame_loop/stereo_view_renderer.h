// SPDX-License-Identifier: MIT
/// @brief What the operator sees (DESIGN.md §2–§3): the newest decoded stereo frame rendered for
///        both eyes, left eye from the left camera and right eye from the right one. The eye
///        poses come in the VR frame; the nominal mapping T_robot_vr (published by the robot
///        once the nominal pose is captured) and each camera's pose at capture time
///        (T_robot_cam, carried by the frame) give T_cam_eye = T_robot_cam⁻¹ · T_robot_vr · T_vr_eye.
///        Shared by the OpenXR, desktop and offscreen modes; needs a current GL context.
///
///        New images reach the GPU through an UploadRing: the decoder writes them into its slots
///        (GL buffer memory), and setFrame only queues the copies into the textures and fences
///        them. Images the decoder had to put into its own memory (no free slot, or before the
///        ring knew their size) are uploaded from there, synchronously.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "calib/system_calibration.h"
#include "xr/frame_loop/depth_worker.h"
#include "xr/render/gpu_camera.h"
#include "xr/render/spherical_renderer.h"
#include "xr/render/upload_ring.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::xr::frame_loop {

class StereoViewRenderer {
 public:
  /// Images (a stereo frame is two) the upload ring holds by default: one pair shown, one
  /// published and unread, two decoding (StereoFrameDecoder's pairs_in_flight), one whose copy is
  /// still in flight.
  static constexpr int kDefaultUploadSlots = 10;

  /// `calibration` needs two cameras; their models are rescaled to the frames' resolution.
  /// `upload_slots` 0: no ring, every image is uploaded from the decoder's memory.
  StereoViewRenderer(const calib::SystemCalibration& calibration, const render::RenderSettings& settings,
                     int upload_slots = kDefaultUploadSlots);
  ~StereoViewRenderer();
  StereoViewRenderer(const StereoViewRenderer&) = delete;
  StereoViewRenderer& operator=(const StereoViewRenderer&) = delete;

  /// Uploads `frame` unless it is the one already on the GPU (the same object); false with the
  /// reason when its size cannot be matched to the calibration or an upload fails.
  bool setFrame(const std::shared_ptr<const video::DecodedStereoFrame>& frame, std::string* error);
  /// The frame on the GPU (null before the first), and when its upload finished (steady ns).
  const std::shared_ptr<const video::DecodedStereoFrame>& frame() const { return frame_; }
  std::int64_t uploadedNs() const { return uploaded_ns_; }
  /// The render thread's time in the last setFrame that took a new frame (the copies issued,
  /// or the uploads from client memory done), ms.
  double lastUploadMs() const { return last_upload_ms_; }
  /// What the decoder takes slots from (null when the ring is off).
  std::shared_ptr<render::UploadSlotSource> uploadSlots() const { return ring_.source(); }
  const render::UploadRing& uploadRing() const { return ring_; }

  /// Renders eye `eye` (0 left, 1 right) into `framebuffer` (width×height of `view`): `view`'s
  /// T_cam_eye is ignored and computed from T_robot_vr and T_vr_eye. Border colour where there
  /// is no frame yet. False with the reason on bad input or a GL failure.
  bool renderEye(int eye, const Eigen::Isometry3d& T_robot_vr, const Eigen::Isometry3d& T_vr_eye,
                 render::EyeView view, GLuint framebuffer, std::string* error);

  /// The same view as renderEye, but each eye pixel gets the camera pixel (x, y) it shows (red,
  /// green) and alpha 1, or alpha 0 where it shows no camera pixel: the projection map that the
  /// ground-truth check (app/bench/truth) follows back into the scene. Render into a float target.
  bool renderProjectionMap(int eye, const Eigen::Isometry3d& T_robot_vr, const Eigen::Isometry3d& T_vr_eye,
                           render::EyeView view, GLuint framebuffer, std::string* error);

  /// Renders with `calibration`'s camera models from the next setFrame on (a calibration applied
  /// live): the cameras are prepared again and the frame on the GPU is dropped, so that next
  /// setFrame uploads even the same frame again. Needs two cameras (false with the reason).
  bool setCalibration(const calib::SystemCalibration& calibration, std::string* error);
  /// The calibration the eyes are rendered with (as given: not rescaled).
  const calib::SystemCalibration& calibration() const { return calibration_; }

  void setSettings(const render::RenderSettings& settings) { settings_ = settings; }
  const render::RenderSettings& settings() const { return settings_; }
  /// The scene proxy (#35) and the depth it takes: with kRadius each eye's sphere has its camera's
  /// estimated radius, with kGrid each eye meets its camera's grid (the mesh path, which cannot,
  /// takes the radius). kFixed, or no estimate yet: settings().radius.
  void setDepth(link::DepthProxy proxy, std::shared_ptr<const DepthEstimate> estimate) {
    depth_proxy_ = proxy;
    depth_ = std::move(estimate);
  }
  link::DepthProxy depthProxy() const { return depth_proxy_; }
  /// The estimate the eyes are rendered with (null: none yet, or the fixed proxy's worker not started).
  const std::shared_ptr<const DepthEstimate>& depth() const { return depth_; }
  /// settings() with eye `eye`'s depth applied (what renderEye and renderProjectionMap use).
  render::RenderSettings settingsForEye(int eye) const;

  /// T_cam_eye = T_robot_cam⁻¹ · T_robot_vr · T_vr_eye, the eye in the camera of the frame on the
  /// GPU (T_robot_cam carried by that frame): the one place it is composed. Nothing without a frame.
  std::optional<Eigen::Isometry3d> cameraFromEye(int eye, const Eigen::Isometry3d& T_robot_vr,
                                                 const Eigen::Isometry3d& T_vr_eye) const;

 private:
  /// view->T_cam_eye = cameraFromEye(…) (needs a frame); false with the reason when that is not a pose.
  bool placeEye(int eye, const Eigen::Isometry3d& T_robot_vr, const Eigen::Isometry3d& T_vr_eye, render::EyeView* view,
                std::string* error) const;

  render::UploadRing ring_;  ///< first: destroyed after the frame and cameras that use its slots
  calib::SystemCalibration calibration_;
  render::RenderSettings settings_;
  link::DepthProxy depth_proxy_ = link::DepthProxy::kFixed;
  std::shared_ptr<const DepthEstimate> depth_;
  render::SphericalRenderer renderer_;
  std::array<std::unique_ptr<render::GpuCamera>, 2> cameras_;
  std::array<std::unique_ptr<render::GpuCamera>, 2> coordinates_;  ///< pixel-coordinate images, made on demand
  std::shared_ptr<const video::DecodedStereoFrame> frame_;
  std::int64_t uploaded_ns_ = 0;
  double last_upload_ms_ = 0;
};

}  // namespace telesphere::xr::frame_loop
