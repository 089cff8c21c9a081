// SPDX-License-Identifier: MIT
/// @brief OffscreenTarget: FBO with a colour texture and a float depth buffer.
#include "shaders/offscreen_target.h"

#include <cstring>

#include "shaders/framebuffer_readback.h"

namespace telesphere::gl {

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
  return readFramebufferRgba8(framebuffer_.id(), GL_COLOR_ATTACHMENT0, width_, height_);
}

std::vector<float> OffscreenTarget::readRgbaF() const {
  return readFramebufferRgbaF(framebuffer_.id(), GL_COLOR_ATTACHMENT0, width_, height_);
}

}  // namespace telesphere::gl
