// SPDX-License-Identifier: MIT
/// @brief The spherical renderer (paper §III-D, DESIGN.md §3): draws what an eye sees of a camera
///        image projected onto a sphere of radius r around the camera, into any framebuffer of
///        the current GL 4.5 context (OpenXR swapchain image, window, offscreen target), with the
///        exact, mesh or look-up-table path and the full6d, orientation3d or fixed mode.
///
/// Eye outside the sphere (|t_cam_eye| > r in full6d): each eye ray takes the sphere's far hit
/// (see sphereFarHit), i.e. the eye looks through the sphere at its inside surface; rays that
/// miss the sphere get the border colour. All three paths and the CPU reference do the same.
///
/// With RenderSettings::depth_grid the exact and LUT paths meet the inverse-depth grid proxy
/// instead of the sphere (depth_proxy.h; the grid is uploaded once per grid object).
#pragma once

#include <map>
#include <string>
#include <tuple>

#include "shaders/gl_objects.h"
#include "xr/render/eye_view.h"
#include "xr/render/gpu_camera.h"

namespace telesphere::xr::render {

class SphericalRenderer {
 public:
  /// Needs a current GL 4.5 core context; programs are compiled on first use per path, camera
  /// model and image format (or in prepare()).
  SphericalRenderer();

  /// Compiles what render() will need for `camera` and `path` now; false with the shader error
  /// (file:line) in out_error.
  bool prepare(const GpuCamera& camera, RenderPath path, std::string* out_error = nullptr);

  /// Renders one eye into the viewport (0, 0, view.width, view.height) of `framebuffer`
  /// (0 = the default framebuffer). Every pixel of the viewport is written. Returns false
  /// without touching the GPU when the view or settings fail their checks (NaN/inf or malformed
  /// pose, bad angles or radius) or the camera has no image; false after a shader error.
  /// The reason goes to out_error. Leaves depth test and scissor disabled.
  bool render(const GpuCamera& camera, const EyeView& view, const RenderSettings& settings,
              GLuint framebuffer, std::string* out_error = nullptr);

 private:
  /// How a program meets the scene: the sphere, or the grid proxy with the march to each ray's
  /// first crossing or with fixed-point steps (a program each: a GPU, llvmpipe among them, may run
  /// both sides of a branch it cannot prove uniform).
  enum class ProxyShader { kSphere, kGridMarch, kGridFixedPoint };

  const gl::GlProgram* program(const GpuCamera& camera, RenderPath path, ProxyShader proxy, std::string* out_error);

  std::map<std::tuple<int, int, int, int>, gl::GlProgram> programs_;
  gl::GlVertexArray empty_vao_;
};

}  // namespace telesphere::xr::render
