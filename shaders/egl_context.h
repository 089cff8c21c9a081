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
  /// The same on the first EGL device that is a GPU (not Mesa's software device, not a context
  /// whose renderer is software()): for work that must not fall to the CPU's cores. Nothing, with
  /// why, where there is none (a machine with Mesa's llvmpipe only).
  static std::unique_ptr<EglContext> createOnHardwareDevice(std::string* out_error = nullptr);

  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// Makes the context current on the calling thread.
  bool makeCurrent() const;

  /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string renderer() const;
  /// Whether the renderer is a software rasterizer (Mesa's llvmpipe, softpipe, swrast): its
  /// "GPU" work runs on this machine's CPU cores.
  bool software() const;

 private:
  EglContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
  static std::unique_ptr<EglContext> contextOn(EGLDisplay display, std::string* out_error);
  EGLDisplay display_;
  EGLContext context_;
};

}  // namespace telesphere::gl
