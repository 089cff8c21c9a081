// SPDX-License-Identifier: MIT
/// @brief RAII owners of GL object names (STYLE.md §15): move-only, deleted in the destructor.
///        They need the context that created them to be current when they are destroyed.
#pragma once

#include <utility>

#include "shaders/gl_api.h"

namespace telesphere::gl {

template <void (*Delete)(GLuint)>
class GlHandle {
 public:
  GlHandle() = default;
  explicit GlHandle(GLuint id) : id_(id) {}
  ~GlHandle() { reset(); }
  GlHandle(GlHandle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  GlHandle& operator=(GlHandle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  GlHandle(const GlHandle&) = delete;
  GlHandle& operator=(const GlHandle&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_ != 0) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

namespace detail {
inline void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
inline void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
inline void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
inline void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
inline void deleteRenderbuffer(GLuint id) { glDeleteRenderbuffers(1, &id); }
inline void deleteProgram(GLuint id) { glDeleteProgram(id); }
inline void deleteShader(GLuint id) { glDeleteShader(id); }
}  // namespace detail

using GlTexture = GlHandle<detail::deleteTexture>;
using GlBuffer = GlHandle<detail::deleteBuffer>;
using GlVertexArray = GlHandle<detail::deleteVertexArray>;
using GlFramebuffer = GlHandle<detail::deleteFramebuffer>;
using GlRenderbuffer = GlHandle<detail::deleteRenderbuffer>;
using GlProgram = GlHandle<detail::deleteProgram>;
using GlShader = GlHandle<detail::deleteShader>;

/// A new texture of `target` (glCreateTextures).
inline GlTexture createTexture(GLenum target) {
  GLuint id = 0;
  glCreateTextures(target, 1, &id);
  return GlTexture(id);
}
inline GlBuffer createBuffer() {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  return GlBuffer(id);
}
inline GlVertexArray createVertexArray() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  return GlVertexArray(id);
}
inline GlFramebuffer createFramebuffer() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  return GlFramebuffer(id);
}
inline GlRenderbuffer createRenderbuffer() {
  GLuint id = 0;
  glCreateRenderbuffers(1, &id);
  return GlRenderbuffer(id);
}

}  // namespace telesphere::gl
