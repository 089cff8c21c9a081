// SPDX-License-Identifier: MIT
/// @brief OpenXrOutput: one OpenXR frame as a DisplayFrame, eyes drawn through the loop's callback.
#include "xr/openxr/openxr_output.h"

namespace telesphere::xr::openxr {

bool OpenXrOutput::frame(const frame_loop::DrawEye& draw, Shown* shown, std::string* error) {
  if (!session_) {
    *error = "no OpenXR session";
    return false;
  }
  frame_loop::DisplayFrame& f = shown->frame;
  bool eye_failed = false;
  const OpenXrRenderEye render = [&](const OpenXrEye& eye) {
    const auto e = std::size_t(eye.eye);
    if (eye.eye == 0) {
      f.index = eye.frame_index;
      f.display_ns = eye.predicted_display_steady_ns;
      f.T_vr_hmd = eye.T_vr_hmd;
      f.head_valid = true;  // the session renders only frames whose view poses are valid
    }
    f.T_vr_eye[e] = eye.T_vr_eye;
    f.views[e].fov = eye.fov;
    f.views[e].width = eye.width;
    f.views[e].height = eye.height;
    if (!draw(f, eye.eye, eye.framebuffer) || (after_eye_ && !after_eye_(eye, error))) {
      eye_failed = true;
      return false;
    }
    return true;
  };
  result_ = OpenXrFrameResult();
  std::string session_error;
  const bool ok = session_->frame(render, read_back_, &result_, &session_error);
  if (eye_failed) return false;  // *error as the eye's work left it
  if (!ok) {
    *error = session_error;
    return false;
  }
  shown->began = result_.waited;
  shown->drawn = result_.submitted;
  shown->shown_ns = result_.predicted_display_steady_ns;
  f.display_ns = result_.predicted_display_steady_ns;
  f.display_period_ns = result_.predicted_display_period_ns;
  f.refresh_ns = result_.predicted_display_time_ns;
  return true;
}

}  // namespace telesphere::xr::openxr
