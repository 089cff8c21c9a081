// SPDX-License-Identifier: MIT
/// @brief The headset run's readback folder (`telesphere-xr openxr --readback-dir`): every
///        swapchain image as PNG, `poses.csv` (per eye: the T_cam_eye, field of view, size,
///        camera frame, visual mode and radius it was rendered with, and the link's cues drawn over
///        it: image saturation, the image's age, eye-camera distance, stream text) and the camera images it
///        showed (YUV planes, once per frame and eye), so that a test can re-render what the
///        headset showed with the double-precision reference and compare.
#pragma once

#include <cstdint>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <utility>

#include "xr/openxr/openxr_session.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/frame_loop/operator_view.h"

namespace telesphere::xr::openxr {

class OpenXrReadbackLog {
 public:
  /// Creates `folder` (and its parents) and starts poses.csv there; null with the reason when it
  /// cannot.
  static std::unique_ptr<OpenXrReadbackLog> open(const std::string& folder, std::string* error);

  /// Image names from now on carry session number `session` (from 1).
  void newSession(int session) { session_ = session; }

  /// After eye `eye` was drawn: its row in poses.csv, with the pose `scene` rendered it with; and,
  /// when `view` (null for the test scene) showed a camera frame not saved yet for this eye, its
  /// planes. `settings` are those the eye was drawn with. False with the reason on a write error.
  bool eyeDrawn(const OpenXrEye& eye, const frame_loop::OperatorScene& scene, const frame_loop::OperatorView* view,
                const render::RenderSettings& settings, std::string* error);

  /// The eye's swapchain image as it was released (sRGB bytes) as PNG; false with the reason.
  bool saveImage(const OpenXrEye& eye, std::string* error) const;

 private:
  explicit OpenXrReadbackLog(std::string folder) : folder_(std::move(folder)) {}
  /// "s<session>_frame<index>_eye<eye>.png"
  std::string imageName(const OpenXrEye& eye) const;

  std::string folder_;
  std::ofstream poses_;
  std::set<std::pair<std::uint64_t, int>> saved_planes_;  ///< (camera frame, eye)
  int session_ = 0;
};

}  // namespace telesphere::xr::openxr
