// SPDX-License-Identifier: MIT
#include "xr/openxr/openxr_mirror.h"

#include "shaders/png_io.h"

namespace telesphere::xr::openxr {

void OpenXrMirror::copyEye(const OpenXrEye& eye) {
  auto& target = eyes_[std::size_t(eye.eye)];
  if (!target || target->width() != eye.width || target->height() != eye.height)
    target = std::make_unique<gl::OffscreenTarget>(eye.width, eye.height, GL_SRGB8_ALPHA8);
  // sRGB swapchain: the bytes as they are; linear swapchain: encoded to sRGB on the way.
  if (!eye.srgb_swapchain) glEnable(GL_FRAMEBUFFER_SRGB);
  glBlitNamedFramebuffer(eye.framebuffer, target->framebuffer(), 0, 0, eye.width, eye.height, 0, 0, eye.width,
                         eye.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glDisable(GL_FRAMEBUFFER_SRGB);
}

bool OpenXrMirror::present(desktop::DesktopWindow& window, std::string* error) {
  if (!ready()) return true;
  return window.present(eyes_[0]->framebuffer(), eyes_[1]->framebuffer(), eyes_[0]->width(), eyes_[0]->height(),
                        error);
}

bool OpenXrMirror::save(desktop::DesktopWindow& window, const std::string& path, std::string* error) {
  if (!ready()) {
    *error = "the mirror never got an eye image";
    return false;
  }
  if (!window.compose(eyes_[0]->framebuffer(), eyes_[1]->framebuffer(), eyes_[0]->width(), eyes_[0]->height(),
                      error))
    return false;
  const auto pixels = window.readBackBufferRgba();
  return gl::writePng(path, window.framebufferWidth(), window.framebufferHeight(), 4, pixels.data(), error);
}

}  // namespace telesphere::xr::openxr
