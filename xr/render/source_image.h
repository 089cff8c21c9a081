// SPDX-License-Identifier: MIT
/// @brief A camera image as the renderer takes it: 8-bit RGB, float (1–4 channels; tests put
///        each texel's own pixel coordinates in it), or JPEG-native YUV planes (Y full size, Cb
///        and Cr subsampled, any factor) that are converted to RGB in the shader, never on the
///        CPU. sample() is the double-precision twin of the GPU's bilinear lookup. YUV images
///        share the decoder's planes (a shared pointer, never a copy of the pixels).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "xr/render/yuv_planes.h"

namespace telesphere::xr::render {

struct SourceImage {
  enum class Format { kRgb8, kFloat, kYuv };

  Format format = Format::kRgb8;
  int width = 0;
  int height = 0;
  int channels = 3;        ///< kRgb8: 3; kFloat: 1..4; kYuv: 3 (planes)
  int chroma_width = 0;    ///< kYuv: Cb/Cr plane size; 0 × 0 for greyscale (a Mono8 camera)
  int chroma_height = 0;
  std::vector<std::uint8_t> bytes;  ///< kRgb8: RGB rows top first
  std::vector<float> floats;        ///< kFloat: rows top first, `channels` per texel
  std::shared_ptr<const YuvPlanes> planes;  ///< kYuv: the Y, Cb, Cr planes (shared, not copied)

  static SourceImage rgb8(int width, int height, std::vector<std::uint8_t> rgb);
  static SourceImage floatImage(int width, int height, int channels, std::vector<float> data);
  /// The decoder's planes as they are (no pixel is copied); sizes taken from them.
  static SourceImage yuv(std::shared_ptr<const YuvPlanes> planes);
  /// Y, then Cb, then Cr concatenated (tests, tools): split into new planes, i.e. copied once.
  /// A buffer of the wrong size gives an image that is not consistent().
  static SourceImage yuv(int width, int height, int chroma_width, int chroma_height,
                         const std::vector<std::uint8_t>& concatenated);

  /// The image whose texel (x, y) holds its own pixel coordinates (x, y) (RG float): rendering
  /// it gives the projection map, in camera pixels.
  static SourceImage pixelCoordinates(int width, int height);

  /// True when the buffers have the sizes the format needs.
  bool consistent() const;

  /// Bilinear sample at camera pixel px (origin at the centre of the top-left pixel), clamped to
  /// the edge, as RGBA in 0..1 (bytes / 255; YUV converted with JFIF BT.601 and clamped; float
  /// channels as stored, missing ones 0 and alpha 1) — what GL_LINEAR + CLAMP_TO_EDGE returns.
  Eigen::Vector4d sample(const Eigen::Vector2d& px) const;
};

}  // namespace telesphere::xr::render
