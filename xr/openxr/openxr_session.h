// SPDX-License-Identifier: MIT
/// @brief An OpenXR session that renders with OpenGL: instance (XR_MNDX_egl_enable on the
///        current EGL context, no display needed), HMD system, stereo view configuration,
///        reference space STAGE else LOCAL, one swapchain per eye (sRGB where offered), the
///        session life cycle (SessionStateMachine) and the frame loop xrWaitFrame →
///        xrBeginFrame → xrLocateViews at the predicted display time → a render callback per
///        eye → projection layer → xrEndFrame. One action, "capture the nominal pose", on the
///        select button of /interaction_profiles/khr/simple_controller in either hand. Every OpenXR call is checked where it is made
///        (TELESPHERE_CHECK_XR). Views whose pose is not valid are not rendered: that frame is
///        ended without layers.
///
/// Threading: create, poll and render on one thread, the one whose GL context is current.
/// One concept: one XrSession's life (about 550 lines) — instance, system, spaces, swapchains and
/// the frame loop share their handles and the order in which OpenXR requires them created and
/// destroyed.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "shaders/gl_api.h"
#include "xr/render/eye_view.h"
#include "xr/openxr/openxr_swapchain_format.h"
#include "xr/openxr/session_state_machine.h"

namespace telesphere::xr::openxr {

/// Why OpenXrSession::create failed.
enum class OpenXrFailure {
  kNone,
  kNoRuntime,  ///< no runtime installed/running (the message says how to get one)
  kNoHmd,      ///< runtime present, no head-mounted display connected
  kNoGraphicsBinding,  ///< the runtime offers no OpenGL binding we can use
  kFailed,     ///< any other failed call (the message names it)
};

struct OpenXrOptions {
  std::string application_name = "telesphere-xr";
  SwapchainColour colour = SwapchainColour::kAuto;
};

/// What the render callback gets for one eye.
struct OpenXrEye {
  int eye = 0;                      ///< 0 left, 1 right
  std::uint64_t frame_index = 0;    ///< counts frames waited for, from 0
  std::int64_t predicted_display_time_ns = 0;  ///< XrTime of the frame (runtime clock, ns)
  std::int64_t predicted_display_steady_ns = 0;  ///< the same instant in the link's steady clock
  Eigen::Isometry3d T_vr_eye;       ///< eye pose in the reference space (OpenXR view frame)
  Eigen::Isometry3d T_vr_hmd;       ///< midpoint of both eyes' poses this frame
  render::Fov fov;                          ///< the eye's XrFovf
  int width = 0, height = 0;        ///< image size, px
  GLuint framebuffer = 0;           ///< draw into viewport (0, 0, width, height) of this FBO
  bool srgb_swapchain = true;       ///< false: the FBO is an sRGB staging texture (see format)
};

/// Renders one eye; false means "this eye could not be rendered" (the frame gets no layer).
using OpenXrRenderEye = std::function<bool(const OpenXrEye&)>;
/// Called after an eye is rendered (and, for linear swapchains, converted), before the image is
/// released: `framebuffer` then holds the swapchain image itself, e.g. for glReadPixels.
using OpenXrReadEye = std::function<void(const OpenXrEye&)>;

/// What one call of OpenXrSession::frame() did.
struct OpenXrFrameResult {
  bool waited = false;     ///< xrWaitFrame … xrEndFrame ran
  bool submitted = false;  ///< xrEndFrame got a projection layer with both views
  bool views_valid = false;
  std::int64_t predicted_display_time_ns = 0;
  /// The same instant in the steady clock (CLOCK_MONOTONIC, the link's clock): through
  /// XR_KHR_convert_timespec_time where offered, else now + the predicted display period.
  std::int64_t predicted_display_steady_ns = 0;
  std::int64_t predicted_display_period_ns = 0;  ///< the runtime's display period
  /// The operator pressed "capture nominal pose" (a controller's select button) since the
  /// last frame (only while FOCUSED).
  bool capture_nominal_pressed = false;
};

class OpenXrSession {
 public:
  /// Creates instance, system, session, space and swapchains. Needs a current OpenGL 4.5
  /// context on this thread: EGL (gl::EglContext, or a DesktopWindow made through EGL) gives the
  /// XR_MNDX_egl_enable binding, GLX (a DesktopWindow with a native context) the Xlib binding of
  /// XR_KHR_opengl_enable. The session renders through it. Nothing, with
  /// the reason in out_error and its kind in out_failure, when that fails.
  static std::unique_ptr<OpenXrSession> create(const OpenXrOptions& options,
                                               std::string* out_error = nullptr,
                                               OpenXrFailure* out_failure = nullptr);
  ~OpenXrSession();
  OpenXrSession(const OpenXrSession&) = delete;
  OpenXrSession& operator=(const OpenXrSession&) = delete;

  /// Handles all pending events (state changes: begins/ends the session; instance loss).
  /// False with the reason when a call failed (lost() tells whether the runtime went away).
  bool pollEvents(std::string* out_error = nullptr);

  /// One frame when the session is running (state().shouldSyncFrames()); otherwise returns at
  /// once with result->waited false. render(eye) is called per eye when the session is
  /// VISIBLE/FOCUSED and both view poses are valid. False with the reason when a call failed.
  /// read_back (may be empty) sees each rendered swapchain image before it is released.
  bool frame(const OpenXrRenderEye& render, const OpenXrReadEye& read_back,
             OpenXrFrameResult* out_result, std::string* out_error = nullptr);

  /// An XrTime in the steady clock (CLOCK_MONOTONIC) through XR_KHR_convert_timespec_time; 0
  /// when the runtime does not offer the conversion.
  std::int64_t steadyNsFromXrTime(std::int64_t xr_time) const;

  /// Ask to quit: xrRequestExitSession while running (the runtime then stops the session).
  bool requestExit(std::string* out_error = nullptr);

  const SessionStateMachine& state() const { return machine_; }
  /// The runtime or session went away (instance loss, XR_ERROR_*_LOST).
  bool lost() const { return machine_.lost(); }

  const std::string& runtimeName() const { return runtime_name_; }   ///< "Monado 25.0.0"
  const std::string& systemName() const { return system_name_; }
  const std::string& graphicsBinding() const { return binding_; }   ///< extension used
  const std::string& referenceSpace() const { return space_name_; } ///< "STAGE" or "LOCAL"
  SwapchainFormatChoice swapchainFormat() const { return format_; }
  int eyeWidth() const { return width_; }
  int eyeHeight() const { return height_; }

  struct Impl;

 private:
  explicit OpenXrSession(std::unique_ptr<Impl> impl);
  bool apply(SessionAction action, std::string* out_error);
  bool handleResult(bool ok, int result);

  std::unique_ptr<Impl> impl_;
  SessionStateMachine machine_;
  std::string runtime_name_, system_name_, binding_, space_name_;
  SwapchainFormatChoice format_;
  int width_ = 0, height_ = 0;
  std::uint64_t frame_index_ = 0;
};

/// Whether the active OpenXR runtime offers instance extension `name`; nothing when no runtime
/// answers.
std::optional<bool> openXrRuntimeOffers(const char* name);

/// The message for "no OpenXR runtime": how to get one (Monado, SteamVR) and how to run
/// without a headset.
std::string noRuntimeHelp();

}  // namespace telesphere::xr::openxr
