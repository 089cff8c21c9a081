// SPDX-License-Identifier: MIT
/// @brief Real JPEGs for the media path's tests: a textured image encoded by the robot's own
///        encoder (restart markers every N MCU rows) and decoded by libjpeg-turbo into its planes.
#pragma once

#include <turbojpeg.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "robot/video/jpeg_encoder.h"

namespace telesphere::link::media::test {

inline std::vector<std::uint8_t> texturedRgb(int w, int h, int seed = 0) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
      p[0] = static_cast<std::uint8_t>(128 + 100 * std::sin((x + seed) * 0.11));
      p[1] = static_cast<std::uint8_t>(128 + 100 * std::cos((y - seed) * 0.13));
      p[2] = static_cast<std::uint8_t>(128 + 100 * std::sin((x + 2 * y) * 0.07));
    }
  return rgb;
}

inline std::vector<std::uint8_t> encodeJpeg(int w, int h, ChromaSubsampling subsampling, int restart_mcu_rows,
                                            int quality = 85, int seed = 0) {
  robot::video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg;
  std::string error;
  const auto rgb = texturedRgb(w, h, seed);
  if (!encoder.encodeRgb(rgb.data(), w, h, w * 3, {quality, subsampling, restart_mcu_rows}, jpeg, &error))
    throw std::runtime_error(error);
  return jpeg;
}

/// The JPEG's planes, decoded as the operator side does (no upsampling); empty when libjpeg-turbo
/// reports an error or a warning (a corrupt stream).
struct Planes {
  std::vector<std::uint8_t> y, u, v;
  int width = 0, height = 0, chroma_width = 0, chroma_height = 0;
  bool ok = false;
};

inline Planes decodePlanes(const std::vector<std::uint8_t>& jpeg) {
  Planes p;
  tjhandle d = tjInitDecompress();
  int w = 0, h = 0, samp = 0, cs = 0;
  if (tjDecompressHeader3(d, jpeg.data(), jpeg.size(), &w, &h, &samp, &cs) == 0) {
    p.width = w;
    p.height = h;
    const bool gray = samp == TJSAMP_GRAY;
    p.y.resize(static_cast<std::size_t>(tjPlaneSizeYUV(0, w, 0, h, samp)));
    if (!gray) {
      p.chroma_width = tjPlaneWidth(1, w, samp);
      p.chroma_height = tjPlaneHeight(1, h, samp);
      p.u.resize(static_cast<std::size_t>(tjPlaneSizeYUV(1, w, 0, h, samp)));
      p.v.resize(p.u.size());
    }
    unsigned char* planes[3] = {p.y.data(), gray ? nullptr : p.u.data(), gray ? nullptr : p.v.data()};
    int strides[3] = {w, p.chroma_width, p.chroma_width};
    p.ok = tjDecompressToYUVPlanes(d, jpeg.data(), jpeg.size(), planes, w, strides, h, TJFLAG_STOPONWARNING) == 0;
  }
  tjDestroy(d);
  return p;
}

}  // namespace telesphere::link::media::test
