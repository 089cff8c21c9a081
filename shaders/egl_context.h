// SPDX-License-Identifier: MIT
/// @brief An OpenGL 4.5 core context without a window: EGL on Mesa's surfaceless platform
///        (EGL_PLATFORM_SURFACELESS_MESA; llvmpipe when there is no GPU), else on the first EGL
///        device (EGL_PLATFORM_DEVICE_EXT: NVIDIA's driver), for tests, benchmarks,
///        the still command and offscreen rendering. Draw into framebuffer objects. Several may
///        exist at once: they share the process's one surfaceless display, which stays
///        initialised until exit.
#pragma once

#include <memory>
#include <string>

#include "shaders/gl_api.h"

namespace telesphere::gl {

class EglContext {
 public:
  /// Creates a surfaceless GL 4.5 core context and makes it current on this thread; nothing,
  /// with the failing EGL call and its error code in out_error, when that is not possible.
  static std::unique_ptr<EglContext> createSurfaceless(std::string* out_error = nullptr);

  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// Makes the context current on the calling thread.
  bool makeCurrent() const;

  /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string renderer() const;

 private:
  EglContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
  EGLDisplay display_;
  EGLContext context_;
};

}  // namespace telesphere::gl
