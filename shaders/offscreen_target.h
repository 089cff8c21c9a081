// SPDX-License-Identifier: MIT
/// @brief A framebuffer object to render into without a window: a colour texture (RGBA8 for
///        pictures, RGBA32F for geometry checks) and a 32-bit float depth buffer. Read-backs
///        return rows top first (image order), the reverse of GL's bottom-first rows.
#pragma once

#include <cstdint>
#include <vector>

#include "shaders/gl_objects.h"

namespace telesphere::gl {

class OffscreenTarget {
 public:
  /// colour_format: GL_RGBA8 or GL_RGBA32F. Needs a current context.
  OffscreenTarget(int width, int height, GLenum colour_format = GL_RGBA8);

  GLuint framebuffer() const { return framebuffer_.id(); }
  GLuint colourTexture() const { return colour_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  /// True when the framebuffer is complete (glCheckNamedFramebufferStatus).
  bool complete() const;

  /// Clears colour to `rgba` and depth to `depth`.
  void clear(float r, float g, float b, float a, float depth = 1.0f) const;

  /// Pixels as RGBA bytes, width·height·4, top row first.
  std::vector<std::uint8_t> readRgba8() const;
  /// Pixels as RGBA floats, width·height·4, top row first.
  std::vector<float> readRgbaF() const;

 private:
  int width_, height_;
  GlTexture colour_;
  GlRenderbuffer depth_;
  GlFramebuffer framebuffer_;
};

}  // namespace telesphere::gl
