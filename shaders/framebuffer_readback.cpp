// SPDX-License-Identifier: MIT
/// @brief readFramebufferRgba8 / readFramebufferRgbaF: glReadPixels with the caller's state kept,
///        rows flipped to image order.
#include "shaders/framebuffer_readback.h"

#include <algorithm>
#include <cstddef>

namespace telesphere::gl {
namespace {

template <typename T>
std::vector<T> readRowsTopFirst(GLuint framebuffer, GLenum read_buffer, int width, int height, GLenum type) {
  std::vector<T> pixels(static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0)) * 4);
  if (pixels.empty()) return pixels;
  GLint read_binding = 0, pack_buffer = 0, pack_alignment = 4;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_binding);
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer);
  glGetIntegerv(GL_PACK_ALIGNMENT, &pack_alignment);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glNamedFramebufferReadBuffer(framebuffer, read_buffer);
  glReadPixels(0, 0, width, height, GL_RGBA, type, pixels.data());
  glPixelStorei(GL_PACK_ALIGNMENT, pack_alignment);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(pack_buffer));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read_binding));
  // GL rows are bottom first; flip to image order.
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row),
                     pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y + 1) * row),
                     pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height - 1 - y) * row));
  return pixels;
}

}  // namespace

std::vector<std::uint8_t> readFramebufferRgba8(GLuint framebuffer, GLenum read_buffer, int width, int height) {
  return readRowsTopFirst<std::uint8_t>(framebuffer, read_buffer, width, height, GL_UNSIGNED_BYTE);
}

std::vector<float> readFramebufferRgbaF(GLuint framebuffer, GLenum read_buffer, int width, int height) {
  return readRowsTopFirst<float>(framebuffer, read_buffer, width, height, GL_FLOAT);
}

}  // namespace telesphere::gl
