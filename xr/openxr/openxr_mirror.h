// SPDX-License-Identifier: MIT
/// @brief Both eyes of the headset, as they were released to the runtime, shown side by side in
///        a desktop window (`telesphere-xr openxr --mirror`) and saved as a PNG at the end. Each
///        eye's swapchain image is copied into an sRGB texture of its own while it is still
///        ours: an sRGB swapchain's bytes as they are, a linear one's encoded to sRGB on the way,
///        so the window shows what the headset's compositor shows either way.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "shaders/offscreen_target.h"
#include "xr/desktop/desktop_window.h"
#include "xr/openxr/openxr_session.h"

namespace telesphere::xr::openxr {

class OpenXrMirror {
 public:
  /// Copies eye `eye`'s image (its framebuffer, still bound to the swapchain image). Needs the
  /// session's GL context current.
  void copyEye(const OpenXrEye& eye);
  /// Both eyes have been copied at least once.
  bool ready() const { return eyes_[0] && eyes_[1]; }
  /// Shows the newest copies in `window` (nothing before ready()); false with the reason.
  bool present(desktop::DesktopWindow& window, std::string* error);
  /// What the window shows now, as a PNG at `path`; false with the reason (never ready: "the
  /// mirror never got an eye image").
  bool save(desktop::DesktopWindow& window, const std::string& path, std::string* error);

 private:
  std::array<std::unique_ptr<gl::OffscreenTarget>, 2> eyes_;
};

}  // namespace telesphere::xr::openxr
