// SPDX-License-Identifier: MIT
/// @brief Reading a framebuffer's pixels back to the CPU in image order (rows top first, the
///        reverse of GL's bottom-first rows): offscreen targets, OpenXR swapchain images and a
///        window's back buffer all read through here.
#pragma once

#include <cstdint>
#include <vector>

#include "shaders/gl_api.h"

namespace telesphere::gl {

/// RGBA bytes of `framebuffer`'s `read_buffer` (GL_COLOR_ATTACHMENT0 for an FBO; GL_BACK for a
/// window's default framebuffer 0), width·height·4, rows top first. Restores the read
/// framebuffer and pixel-pack buffer bindings and the pack alignment it changes, so it can be
/// called in the middle of someone else's drawing. Needs a current context.
std::vector<std::uint8_t> readFramebufferRgba8(GLuint framebuffer, GLenum read_buffer, int width, int height);
/// The same as RGBA floats (for geometry checks on GL_RGBA32F targets).
std::vector<float> readFramebufferRgbaF(GLuint framebuffer, GLenum read_buffer, int width, int height);

}  // namespace telesphere::gl
