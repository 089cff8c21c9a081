// SPDX-License-Identifier: MIT
/// @brief OffscreenTarget: FBO with a colour texture and a float depth buffer.
#include "shaders/offscreen_target.h"

#include <algorithm>
#include <cstring>

namespace telesphere::gl {
namespace {

template <typename T>
std::vector<T> readRows(GLuint framebuffer, int width, int height, GLenum type) {
  std::vector<T> pixels(static_cast<std::size_t>(width) * height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glReadPixels(0, 0, width, height, GL_RGBA, type, pixels.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  // GL rows are bottom first; flip to image order.
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(pixels.begin() + static_cast<std::ptrdiff_t>(y * row),
                     pixels.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                     pixels.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * row));
  return pixels;
}

}  // namespace

OffscreenTarget::OffscreenTarget(int width, int height, GLenum colour_format)
    : width_(width), height_(height) {
  colour_ = createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(colour_.id(), 1, colour_format, width, height);
  glTextureParameteri(colour_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(colour_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  depth_ = createRenderbuffer();
  glNamedRenderbufferStorage(depth_.id(), GL_DEPTH_COMPONENT32F, width, height);
  framebuffer_ = createFramebuffer();
  glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, colour_.id(), 0);
  glNamedFramebufferRenderbuffer(framebuffer_.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                 depth_.id());
}

bool OffscreenTarget::complete() const {
  return glCheckNamedFramebufferStatus(framebuffer_.id(), GL_FRAMEBUFFER) ==
         GL_FRAMEBUFFER_COMPLETE;
}

void OffscreenTarget::clear(float r, float g, float b, float a, float depth) const {
  const float colour[4] = {r, g, b, a};
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, colour);
  glClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &depth);
}

std::vector<std::uint8_t> OffscreenTarget::readRgba8() const {
  return readRows<std::uint8_t>(framebuffer_.id(), width_, height_, GL_UNSIGNED_BYTE);
}

std::vector<float> OffscreenTarget::readRgbaF() const {
  return readRows<float>(framebuffer_.id(), width_, height_, GL_FLOAT);
}

}  // namespace telesphere::gl
