// SPDX-License-Identifier: MIT
/// @brief An OpenXR session as the operator loop's output: display frames paced by xrWaitFrame,
///        the head and eye poses located by the runtime at the predicted display time, each eye
///        drawn into its swapchain image and submitted as a projection layer. The display time is
///        given in the steady clock (for the robot and the telemetry) and in the runtime's XrTime
///        (skipped refreshes are counted on that). Sessions come and go (a runtime that restarts):
///        setSession points the output at the current one.
#pragma once

#include <functional>

#include "xr/openxr/openxr_session.h"
#include "xr/frame_loop/operator_loop.h"

namespace telesphere::xr::openxr {

class OpenXrOutput final : public frame_loop::OperatorOutput {
 public:
  /// After an eye was drawn, before its image is converted or released (e.g. a log of the pose it
  /// was drawn with); false (reason in *error) ends the frame and the run.
  using AfterEye = std::function<bool(const OpenXrEye& eye, std::string* error)>;

  explicit OpenXrOutput(AfterEye after_eye = {}, OpenXrReadEye read_back = {})
      : after_eye_(std::move(after_eye)), read_back_(std::move(read_back)) {}

  /// The session frames come from (must outlive its use; null: none).
  void setSession(OpenXrSession* session) { session_ = session; }
  /// One OpenXrSession::frame. began false when the session does not sync frames now.
  bool frame(const frame_loop::DrawEye& draw, Shown* shown, std::string* error) override;
  /// What the last frame's OpenXrSession::frame reported (e.g. capture_nominal_pressed).
  const OpenXrFrameResult& lastResult() const { return result_; }

 private:
  AfterEye after_eye_;
  OpenXrReadEye read_back_;
  OpenXrSession* session_ = nullptr;
  OpenXrFrameResult result_;
};

}  // namespace telesphere::xr::openxr
