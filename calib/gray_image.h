// SPDX-License-Identifier: MIT
/// @brief An 8-bit single-channel image, row-major without padding (what the Aprilgrid renderer
///        writes and the detectors read), so that public calib headers need no OpenCV.
#pragma once

#include <cstdint>
#include <vector>

namespace telesphere::calib {

struct GrayImage {
  int width = 0;   ///< px
  int height = 0;  ///< px
  std::vector<std::uint8_t> pixels;  ///< width·height values, row v at pixels[v·width]

  GrayImage() = default;
  GrayImage(int w, int h, std::uint8_t fill = 0)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}
  std::uint8_t& at(int u, int v) { return pixels[static_cast<std::size_t>(v) * width + u]; }
  std::uint8_t at(int u, int v) const { return pixels[static_cast<std::size_t>(v) * width + u]; }
};

}  // namespace telesphere::calib
