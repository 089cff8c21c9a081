// SPDX-License-Identifier: MIT
/// @brief One camera on the GPU: its model (as shader uniforms), its current image as textures
///        (RGB8, float, or three YUV planes), and, built on first use, the tessellated sphere of
///        the mesh path and the direction→pixel table of the look-up-table path; the inverse-depth
///        grid of the grid proxy as a texture. Needs the GL
///        context it was created in to be current for every call and for its destruction.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "calib/generic_camera.h"
#include "shaders/gl_objects.h"
#include "xr/render/depth_proxy.h"
#include "xr/render/source_image.h"

namespace telesphere::xr::render {

class GpuCamera {
 public:
  /// `camera` calibrated for image_width × image_height images (px, > 0).
  GpuCamera(const calib::GenericCamera& camera, int image_width, int image_height);
  ~GpuCamera();
  GpuCamera(const GpuCamera&) = delete;
  GpuCamera& operator=(const GpuCamera&) = delete;

  /// Uploads a new image. False (nothing changed) when it is inconsistent or not the calibrated
  /// size, with the reason in out_error. Changing the format reallocates the textures.
  bool upload(const SourceImage& image, std::string* out_error = nullptr);
  bool hasImage() const { return format_set_; }
  SourceImage::Format format() const { return format_; }

  const calib::GenericCamera& camera() const { return camera_; }
  int imageWidth() const { return width_; }
  int imageHeight() const { return height_; }

  /// GLSL model index (TS_MODEL): 0 ds, 1 eucm, 2 kb4, 3 pinhole.
  int modelIndex() const { return model_index_; }
  /// Parameters in model order (unused entries 0) and the validity bound u_cam_limit.
  const std::array<float, 8>& shaderParams() const { return params_; }
  float shaderLimit() const { return limit_; }

  /// Binds the image textures to units 0 (RGB/float/Y), 1 (Cb), 2 (Cr).
  void bindImage() const;

  struct Mesh {
    gl::GlVertexArray vao;
    gl::GlBuffer vertices, indices;
    int index_count = 0;
    int rings = 0, segments = 0;
  };
  /// The sphere mesh of the mesh path (built once per tessellation): rings in θ from 0 to the
  /// largest angle the image shows (or the model's maxAngle when the image circle lies inside
  /// the sensor), each vertex the unit direction plus its camera pixel projected in double.
  const Mesh& mesh(int rings, int segments) const;
  /// The RG32F look-up table (size × size) of the LUT path, built once per size in double.
  GLuint lut(int size) const;
  /// The R32F texture of a grid proxy (the grid's cols × rows, longitude repeating, latitude
  /// clamped), uploaded when `grid` is not the grid uploaded last (which the camera holds on to).
  GLuint inverseDepthTexture(const std::shared_ptr<const InverseDepthGrid>& grid) const;
  /// gridProxyParams of `grid` (its largest value takes a pass over every tile), computed again
  /// only for another grid object or other settings: once per grid, not per eye and frame.
  const GridProxyParams& gridParams(const std::shared_ptr<const InverseDepthGrid>& grid, double edge_slope_per_m_per_deg,
                                    double march_step_tiles) const;

 private:
  calib::GenericCamera camera_;
  int width_, height_;
  int model_index_ = 0;
  std::array<float, 8> params_{};
  float limit_ = 0.0f;
  bool format_set_ = false;
  SourceImage::Format format_ = SourceImage::Format::kRgb8;
  int channels_ = 0, chroma_width_ = 0, chroma_height_ = 0;
  std::array<gl::GlTexture, 3> textures_;
  mutable std::unique_ptr<Mesh> mesh_;
  mutable gl::GlTexture lut_;
  mutable int lut_size_ = 0;
  mutable gl::GlTexture inverse_depth_;
  mutable std::shared_ptr<const InverseDepthGrid> inverse_depth_grid_;
  struct CachedGridParams {
    std::shared_ptr<const InverseDepthGrid> grid;
    double edge_slope_per_m_per_deg = 0, march_step_tiles = 0;
    GridProxyParams params;
  };
  mutable CachedGridParams grid_params_;
};

}  // namespace telesphere::xr::render
