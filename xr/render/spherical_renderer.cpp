// SPDX-License-Identifier: MIT
/// @brief SphericalRenderer: program cache, uniforms and draw calls of the three paths.
#include "xr/render/spherical_renderer.h"

#include <Eigen/Geometry>
#include <cmath>

#include "shaders/shader_program.h"
#include "xr/render/depth_proxy.h"
#include "xr/render/sphere_geometry.h"

namespace telesphere::xr::render {

SphericalRenderer::SphericalRenderer() : empty_vao_(gl::createVertexArray()) {}

const gl::GlProgram* SphericalRenderer::program(const GpuCamera& camera, RenderPath path, ProxyShader proxy,
                                                std::string* out_error) {
  const bool depth_grid = proxy != ProxyShader::kSphere;
  const bool yuv = camera.format() == SourceImage::Format::kYuv;
  const auto key = std::make_tuple(static_cast<int>(path), camera.modelIndex(), int(yuv), static_cast<int>(proxy));
  if (auto it = programs_.find(key); it != programs_.end()) return &it->second;
  const std::vector<std::string> defines = {"TS_MODEL " + std::to_string(camera.modelIndex()),
                                            std::string("TS_SOURCE_YUV ") + (yuv ? "1" : "0"),
                                            std::string("TS_DEPTH_GRID ") + (depth_grid ? "1" : "0"),
                                            "TS_GRID_STEPS " + std::to_string(kGridProxySteps),
                                            std::string("TS_GRID_MARCH ") + (proxy == ProxyShader::kGridMarch ? "1" : "0"),
                                            "TS_GRID_MARCH_MAX " + std::to_string(kGridMarchMaxSteps)};
  std::optional<gl::GlProgram> p;
  switch (path) {
    case RenderPath::kExact:
      p = gl::loadProgram("sphere_fullscreen.vert", "sphere_exact.frag", defines, out_error);
      break;
    case RenderPath::kMesh:
      p = gl::loadProgram("sphere_mesh.vert", "sphere_mesh.frag", defines, out_error);
      break;
    case RenderPath::kLut:
      p = gl::loadProgram("sphere_fullscreen.vert", "sphere_lut.frag", defines, out_error);
      break;
  }
  if (!p) return nullptr;
  return &programs_.emplace(key, std::move(*p)).first->second;
}

bool SphericalRenderer::prepare(const GpuCamera& camera, RenderPath path, std::string* out_error) {
  return program(camera, path, ProxyShader::kSphere, out_error) != nullptr;
}

bool SphericalRenderer::render(const GpuCamera& camera, const EyeView& view,
                               const RenderSettings& settings, GLuint framebuffer,
                               std::string* out_error) {
  std::optional<std::string> problem = checkEyeView(view);
  if (!problem) problem = checkRenderSettings(settings);
  if (!problem && !camera.hasImage()) problem = "the camera has no image yet";
  if (problem) {
    if (out_error) *out_error = *problem;
    return false;
  }
  const ProxyShader proxy = !settings.depth_grid                              ? ProxyShader::kSphere
                            : std::isfinite(settings.grid_march_step_tiles) ? ProxyShader::kGridMarch
                                                                            : ProxyShader::kGridFixedPoint;
  const gl::GlProgram* prog = program(camera, settings.path, proxy, out_error);
  if (!prog) return false;
  const GLuint id = prog->id();

  const Eigen::Isometry3d T_cam_eye = effectiveT_cam_eye(view, settings);
  const Eigen::Vector3d o = T_cam_eye.translation();
  const Eigen::Vector4f& border = settings.border_rgba;

  glProgramUniform4f(id, glGetUniformLocation(id, "u_border"), border[0], border[1], border[2],
                     border[3]);
  glProgramUniform1f(id, glGetUniformLocation(id, "u_image_gain"), settings.image_gain);
  glProgramUniform1f(id, glGetUniformLocation(id, "u_image_saturation"), settings.image_saturation);
  glProgramUniform2f(id, glGetUniformLocation(id, "u_image_size"), float(camera.imageWidth()),
                     float(camera.imageHeight()));
  glProgramUniform1fv(id, glGetUniformLocation(id, "u_cam"), 8, camera.shaderParams().data());
  glProgramUniform1f(id, glGetUniformLocation(id, "u_cam_limit"), camera.shaderLimit());

  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, view.width, view.height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  camera.bindImage();
  glUseProgram(id);

  if (settings.path == RenderPath::kMesh) {
    const auto& mesh = camera.mesh(settings.mesh_rings, settings.mesh_segments);
    // Near plane at r/1000 (sphere points nearer than that are clipped); far plane at infinity.
    const Eigen::Matrix4d clip_from_sphere =
        clipFromEye(view.fov, 1e-3 * settings.radius) * T_cam_eye.inverse().matrix() *
        Eigen::Vector4d(settings.radius, settings.radius, settings.radius, 1.0).asDiagonal();
    const Eigen::Matrix4f m = clip_from_sphere.cast<float>();
    glProgramUniformMatrix4fv(id, glGetUniformLocation(id, "u_clip_from_sphere"), 1, GL_FALSE,
                              m.data());
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, view.width, view.height);
    glClearColor(border[0], border[1], border[2], border[3]);
    glClearDepth(0.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    // Farthest wins: outside the sphere the far side is shown, as in the exact path.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glBindVertexArray(mesh.vao.id());
    glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    glDisable(GL_SCISSOR_TEST);
  } else {
    const Eigen::Matrix3f R = T_cam_eye.linear().cast<float>();
    glProgramUniformMatrix3fv(id, glGetUniformLocation(id, "u_R_cam_eye"), 1, GL_FALSE, R.data());
    glProgramUniform4f(id, glGetUniformLocation(id, "u_tan"), float(std::tan(view.fov.angle_left)),
                       float(std::tan(view.fov.angle_right)), float(std::tan(view.fov.angle_down)),
                       float(std::tan(view.fov.angle_up)));
    glProgramUniform3f(id, glGetUniformLocation(id, "u_origin_cam"), float(o.x()), float(o.y()),
                       float(o.z()));
    glProgramUniform1f(id, glGetUniformLocation(id, "u_sphere_c"),
                       float(o.squaredNorm() - settings.radius * settings.radius));
    if (settings.depth_grid) {
      const GridProxyParams& grid =
          camera.gridParams(settings.depth_grid, settings.grid_edge_slope_per_m_per_deg, settings.grid_march_step_tiles);
      glProgramUniform2f(id, glGetUniformLocation(id, "u_radius_range"), float(kMinProxyRadiusM), float(kMaxProxyRadiusM));
      // Infinity (bilinear everywhere) as the largest float: no jump exceeds it.
      glProgramUniform1f(id, glGetUniformLocation(id, "u_edge_jump"),
                         float(std::min(grid.edge_jump_per_m, double(std::numeric_limits<float>::max()))));
      glProgramUniform2f(id, glGetUniformLocation(id, "u_rho_range"), float(grid.inverse_depth_bottom_per_m),
                         float(grid.inverse_depth_top_per_m));
      if (proxy == ProxyShader::kGridMarch)
        glProgramUniform1f(id, glGetUniformLocation(id, "u_march_step_rad"), float(grid.march_step_rad));
      glBindTextureUnit(4, camera.inverseDepthTexture(settings.depth_grid));
    }
    if (settings.path == RenderPath::kLut) {
      glProgramUniform1f(id, glGetUniformLocation(id, "u_max_angle"),
                         float(camera.camera().maxAngle()));
      glBindTextureUnit(3, camera.lut(settings.lut_size));
    }
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(empty_vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  return true;
}

}  // namespace telesphere::xr::render
