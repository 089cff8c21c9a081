// SPDX-License-Identifier: MIT
/// @brief One 8-bit YUV 4:2:0 image in three planes, JPEG's colour space (JFIF: BT.601, full range):
///        what a JPEG encoder compresses from and what the operator's decoder hands the renderer,
///        so a camera image can go from the sensor to the encoder without RGB in between (#34).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace telesphere::robot::cameras {

struct Yuv420Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> y;  ///< width × height, rows width bytes apart
  std::vector<std::uint8_t> u;  ///< Cb: chromaWidth() × chromaHeight(), one sample per 2×2 pixels
  std::vector<std::uint8_t> v;  ///< Cr: as u

  /// Odd sizes: the last column (row) of chroma covers one image column (row).
  int chromaWidth() const { return (width + 1) / 2; }
  int chromaHeight() const { return (height + 1) / 2; }

  /// Sets the size; the planes keep their memory when it does not grow (no allocation per frame).
  void resize(int new_width, int new_height) {
    width = new_width;
    height = new_height;
    y.resize(static_cast<std::size_t>(width) * height);
    u.resize(static_cast<std::size_t>(chromaWidth()) * chromaHeight());
    v.resize(u.size());
  }
};

}  // namespace telesphere::robot::cameras
