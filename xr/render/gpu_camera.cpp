// SPDX-License-Identifier: MIT
/// @brief GpuCamera: model uniforms, texture upload, mesh and look-up-table construction.
#include "xr/render/gpu_camera.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <vector>

namespace telesphere::xr::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Float texture formats by channel count.
constexpr GLenum kFloatInternal[] = {GL_R32F, GL_RG32F, GL_RGB32F, GL_RGBA32F};
constexpr GLenum kFloatFormat[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};

gl::GlTexture makeTexture(GLenum internal, int w, int h) {
  gl::GlTexture t = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, internal, w, h);
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

Eigen::Vector3d direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// The largest angle from the optical axis among the image's border pixels, or nothing when
/// some border pixel has no ray (the image circle lies inside the sensor).
std::optional<double> borderMaxAngle(const calib::GenericCamera& camera, int w, int h) {
  const int step = std::max(1, (w + h) / 1024);
  double max_angle = 0.0;
  const auto visit = [&](double x, double y) {
    Eigen::Vector3d d;
    if (!camera.unproject(Eigen::Vector2d(x, y), d)) return false;
    max_angle = std::max(max_angle, std::atan2(d.head<2>().norm(), d.z()));
    return true;
  };
  for (int x = 0; x <= w; x += step)
    if (!visit(x - 0.5, -0.5) || !visit(x - 0.5, h - 0.5)) return std::nullopt;
  for (int y = 0; y <= h; y += step)
    if (!visit(-0.5, y - 0.5) || !visit(w - 0.5, y - 0.5)) return std::nullopt;
  if (!visit(w - 0.5, h - 0.5)) return std::nullopt;
  return max_angle;
}

}  // namespace

GpuCamera::GpuCamera(const calib::GenericCamera& camera, int image_width, int image_height)
    : camera_(camera), width_(image_width), height_(image_height) {
  camera_.visit([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    const auto& p = model.params();
    for (int i = 0; i < Model::kNumParams; ++i) params_[static_cast<std::size_t>(i)] = float(p[i]);
    const double max_angle = model.maxAngle();
    if constexpr (std::is_same_v<Model, calib::DoubleSphereCamera<double>>) {
      model_index_ = 0;
      limit_ = float(-std::cos(max_angle));  // w2, exactly as the C++ object holds it
    } else if constexpr (std::is_same_v<Model, calib::ExtendedUnifiedCamera<double>>) {
      model_index_ = 1;
      const double alpha = p[4];
      limit_ = float(alpha > 0.5 ? (1.0 - alpha) / alpha : alpha / (1.0 - alpha));
    } else if constexpr (std::is_same_v<Model, calib::KannalaBrandtCamera<double>>) {
      model_index_ = 2;
      limit_ = float(max_angle);
    } else {
      model_index_ = 3;
      const double t = std::tan(max_angle);
      limit_ = float(std::min(t * t, 1e30));
    }
  });
}

GpuCamera::~GpuCamera() = default;

bool GpuCamera::upload(const SourceImage& image, std::string* out_error) {
  if (!image.consistent() || image.width != width_ || image.height != height_) {
    if (out_error) {
      std::ostringstream os;
      os << "camera image " << image.width << "x" << image.height
         << (image.consistent() ? "" : " (buffer sizes inconsistent)") << " does not match the "
         << width_ << "x" << height_ << " calibration";
      *out_error = os.str();
    }
    return false;
  }
  const bool same_layout = format_set_ && image.format == format_ && image.channels == channels_ &&
                           image.chroma_width == chroma_width_ &&
                           image.chroma_height == chroma_height_;
  if (!same_layout) {
    for (auto& t : textures_) t.reset();
    switch (image.format) {
      case SourceImage::Format::kRgb8: textures_[0] = makeTexture(GL_RGBA8, width_, height_); break;
      case SourceImage::Format::kFloat:
        textures_[0] = makeTexture(kFloatInternal[image.channels - 1], width_, height_);
        break;
      case SourceImage::Format::kYuv:
        textures_[0] = makeTexture(GL_R8, width_, height_);
        if (image.chroma_width == 0) {  // greyscale: neutral chroma (128) from 1×1 planes
          const std::uint8_t neutral = 128;
          glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
          for (int plane = 1; plane <= 2; ++plane) {
            textures_[plane] = makeTexture(GL_R8, 1, 1);
            glTextureSubImage2D(textures_[plane].id(), 0, 0, 0, 1, 1, GL_RED, GL_UNSIGNED_BYTE, &neutral);
          }
          break;
        }
        textures_[1] = makeTexture(GL_R8, image.chroma_width, image.chroma_height);
        textures_[2] = makeTexture(GL_R8, image.chroma_width, image.chroma_height);
        break;
    }
    format_ = image.format;
    channels_ = image.channels;
    chroma_width_ = image.chroma_width;
    chroma_height_ = image.chroma_height;
    format_set_ = true;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  switch (image.format) {
    case SourceImage::Format::kRgb8:
      glTextureSubImage2D(textures_[0].id(), 0, 0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE,
                          image.bytes.data());
      break;
    case SourceImage::Format::kFloat:
      glTextureSubImage2D(textures_[0].id(), 0, 0, 0, width_, height_,
                          kFloatFormat[image.channels - 1], GL_FLOAT, image.floats.data());
      break;
    case SourceImage::Format::kYuv: {
      // Straight from the decoder's planes (consistent() checked their sizes): no CPU copy. From
      // an upload slot the source is GL buffer memory: the calls only queue the copies.
      const YuvPlanes& p = *image.planes;
      const auto source = [&](std::span<const std::uint8_t> plane, std::size_t slot_offset) -> const void* {
        return p.slot ? reinterpret_cast<const void*>(slot_offset) : plane.data();
      };
      if (p.slot) glBindBuffer(GL_PIXEL_UNPACK_BUFFER, p.slot->buffer);
      glTextureSubImage2D(textures_[0].id(), 0, 0, 0, width_, height_, GL_RED, GL_UNSIGNED_BYTE,
                          source(p.yPlane(), p.slot ? p.slot->y_offset : 0));
      if (chroma_width_ != 0) {  // greyscale: the neutral chroma planes stay
        glTextureSubImage2D(textures_[1].id(), 0, 0, 0, chroma_width_, chroma_height_, GL_RED, GL_UNSIGNED_BYTE,
                            source(p.uPlane(), p.slot ? p.slot->u_offset : 0));
        glTextureSubImage2D(textures_[2].id(), 0, 0, 0, chroma_width_, chroma_height_, GL_RED, GL_UNSIGNED_BYTE,
                            source(p.vPlane(), p.slot ? p.slot->v_offset : 0));
      }
      if (p.slot) glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
      break;
    }
  }
  return true;
}

void GpuCamera::bindImage() const {
  for (GLuint unit = 0; unit < 3; ++unit)
    if (textures_[unit]) glBindTextureUnit(unit, textures_[unit].id());
}

const GpuCamera::Mesh& GpuCamera::mesh(int rings, int segments) const {
  if (mesh_ && mesh_->rings == rings && mesh_->segments == segments) return *mesh_;
  const double theta_limit = std::min(camera_.maxAngle(), kPi) - 1e-6;
  double theta_end = theta_limit;
  if (const auto border = borderMaxAngle(camera_, width_, height_))
    theta_end = std::min(theta_limit, *border * (1.0 + 2.0 / rings) + 1e-3);

  std::vector<float> vertices;
  vertices.reserve(static_cast<std::size_t>(rings + 1) * (segments + 1) * 5);
  for (int i = 0; i <= rings; ++i) {
    const double theta = theta_end * i / rings;
    for (int j = 0; j <= segments; ++j) {
      const Eigen::Vector3d d = direction(theta, 2.0 * kPi * j / segments);
      Eigen::Vector2d px;
      // Inside maxAngle every direction projects; a failure (rounding at the limit) is sent
      // far outside the image, so its triangles show the border colour.
      if (!camera_.project(d, px)) px.setConstant(-1e6);
      vertices.insert(vertices.end(), {float(d.x()), float(d.y()), float(d.z()), float(px.x()),
                                       float(px.y())});
    }
  }
  std::vector<GLuint> indices;
  indices.reserve(static_cast<std::size_t>(rings) * segments * 6);
  const auto at = [&](int i, int j) { return GLuint(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i > 0) indices.insert(indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
      indices.insert(indices.end(), {at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
    }

  auto m = std::make_unique<Mesh>();
  m->rings = rings;
  m->segments = segments;
  m->index_count = static_cast<int>(indices.size());
  m->vertices = gl::createBuffer();
  glNamedBufferStorage(m->vertices.id(), GLsizeiptr(vertices.size() * sizeof(float)),
                       vertices.data(), 0);
  m->indices = gl::createBuffer();
  glNamedBufferStorage(m->indices.id(), GLsizeiptr(indices.size() * sizeof(GLuint)),
                       indices.data(), 0);
  m->vao = gl::createVertexArray();
  const GLuint vao = m->vao.id();
  glVertexArrayVertexBuffer(vao, 0, m->vertices.id(), 0, 5 * sizeof(float));
  glVertexArrayElementBuffer(vao, m->indices.id());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribFormat(vao, 1, 2, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
  glVertexArrayAttribBinding(vao, 1, 0);
  mesh_ = std::move(m);
  return *mesh_;
}

GLuint GpuCamera::lut(int size) const {
  if (lut_ && lut_size_ == size) return lut_.id();
  // Directions beyond the model's limit (the shader shows the border there, by its exact θ test)
  // repeat the limit's pixel, so that interpolation next to the limit stays continuous.
  const double theta_clamp = std::min(camera_.maxAngle(), kPi) - 1e-4;
  std::vector<float> table(static_cast<std::size_t>(size) * size * 2);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double qx = (i + 0.5) / size * 2.0 - 1.0, qy = (j + 0.5) / size * 2.0 - 1.0;
      const double theta = std::min(kPi * std::hypot(qx, qy), theta_clamp);
      Eigen::Vector2d px;
      if (!camera_.project(direction(theta, std::atan2(qy, qx)), px)) px.setConstant(-1e6);
      const std::size_t k = (static_cast<std::size_t>(j) * size + i) * 2;
      table[k] = float(px.x());
      table[k + 1] = float(px.y());
    }
  }
  lut_ = makeTexture(GL_RG32F, size, size);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(lut_.id(), 0, 0, 0, size, size, GL_RG, GL_FLOAT, table.data());
  lut_size_ = size;
  return lut_.id();
}

GLuint GpuCamera::inverseDepthTexture(const std::shared_ptr<const InverseDepthGrid>& grid) const {
  if (grid == inverse_depth_grid_ && inverse_depth_) return inverse_depth_.id();
  if (!inverse_depth_grid_ || grid->rows() != inverse_depth_grid_->rows() || grid->cols() != inverse_depth_grid_->cols()) {
    inverse_depth_ = makeTexture(GL_R32F, grid->cols(), grid->rows());
    glTextureParameteri(inverse_depth_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);  // round the longitude seam
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(inverse_depth_.id(), 0, 0, 0, grid->cols(), grid->rows(), GL_RED, GL_FLOAT, grid->data());
  inverse_depth_grid_ = grid;
  return inverse_depth_.id();
}

const GridProxyParams& GpuCamera::gridParams(const std::shared_ptr<const InverseDepthGrid>& grid,
                                             double edge_slope_per_m_per_deg, double march_step_tiles) const {
  CachedGridParams& c = grid_params_;
  if (c.grid != grid || c.edge_slope_per_m_per_deg != edge_slope_per_m_per_deg || c.march_step_tiles != march_step_tiles)
    c = {grid, edge_slope_per_m_per_deg, march_step_tiles, gridProxyParams(*grid, edge_slope_per_m_per_deg, march_step_tiles)};
  return c.params;
}

}  // namespace telesphere::xr::render
