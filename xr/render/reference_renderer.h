// SPDX-License-Identifier: MIT
/// @brief The double-precision CPU reference of the spherical renderer: same inputs (camera
///        model, image, eye view, settings), same outputs (RGBA per eye pixel, rows top first) as
///        the GL paths, which are tested against it (STYLE.md §12, §21). Slow; for tests, the
///        benchmark's error columns and tools, never for frames.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <ostream>
#include <vector>

#include "calib/generic_camera.h"
#include "xr/render/eye_view.h"
#include "xr/render/source_image.h"

namespace telesphere::xr::render {

/// RGBA float pixels, rows top first.
struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  ///< width·height·4
  Eigen::Vector4f at(int x, int y) const {
    return Eigen::Map<const Eigen::Vector4f>(&rgba[(static_cast<std::size_t>(y) * width + x) * 4]);
  }
};

/// The camera pixel that eye pixel (col, row) shows: eye ray (through the pixel centre) → far
/// sphere hit (or the grid proxy's point, settings.depth_grid) → camera projection; nothing when the ray misses the sphere, the model has no
/// projection for the point, or the pixel lies outside [−0.5, W − 0.5] × [−0.5, H − 0.5] of an
/// image_width × image_height image. Preconditions: view and settings pass their checks.
std::optional<Eigen::Vector2d> referenceCameraPixel(const calib::GenericCamera& camera,
                                                    int image_width, int image_height,
                                                    const EyeView& view,
                                                    const RenderSettings& settings, double col,
                                                    double row);

/// Renders one eye in double precision: the bilinear sample of `image` at referenceCameraPixel,
/// or settings.border_rgba. Nothing when the view or settings fail their checks or the image is
/// inconsistent (mirrors SphericalRenderer::render). settings.path is ignored: this is exact.
std::optional<RgbaImage> renderReference(const calib::GenericCamera& camera,
                                         const SourceImage& image, const EyeView& view,
                                         const RenderSettings& settings);

/// How a rendered projection map differs from the reference, in camera pixels.
struct ProjectionMapError {
  double max_px = 0.0;
  double mean_px = 0.0;
  double p999_px = 0.0;       ///< 99.9 % of the pixels valid in both are at most this far apart
  int compared = 0;           ///< pixels valid in both
  int validity_mismatch = 0;  ///< pixels valid in one and border in the other
  int total = 0;
};

/// "max … px, p99.9 … px, mean … px over N pixels, M of T differ in validity".
std::ostream& operator<<(std::ostream& os, const ProjectionMapError& e);

/// Compares `rgba` (view.width·view.height·4 floats, rows top first), rendered from
/// `coordinates` = SourceImage::pixelCoordinates(W, H) with a border colour whose alpha is 0, with
/// the reference: per pixel the distance between the rendered (R, G) and the reference's
/// bilinear sample of the same image at referenceCameraPixel (which is that pixel itself inside
/// the image).
ProjectionMapError compareProjectionMap(const std::vector<float>& rgba,
                                        const calib::GenericCamera& camera,
                                        const SourceImage& coordinates, const EyeView& view,
                                        const RenderSettings& settings);

}  // namespace telesphere::xr::render
