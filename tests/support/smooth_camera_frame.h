// SPDX-License-Identifier: MIT
/// @brief A smooth RGB8 camera frame (what a camera sees; random pixels are JPEG's worst case), one
///        helper for the video tests that stream frames end to end.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "robot/cameras/camera_source.h"

namespace telesphere::test {

inline robot::cameras::CameraFrame smoothFrame(int w, int h, double phase) {
  robot::cameras::CameraFrame f;
  f.width = w;
  f.height = h;
  f.format = robot::cameras::PixelFormat::kRgb8;
  f.stride_bytes = w * 3;
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(std::size_t(w) * std::size_t(h) * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        (*pixels)[std::size_t((y * w + x) * 3 + c)] =
            std::uint8_t(128 + 100 * std::sin(x / 37.0 + phase + c) * std::cos(y / 29.0 - c));
  f.pixels = pixels;
  return f;
}

}  // namespace telesphere::test
