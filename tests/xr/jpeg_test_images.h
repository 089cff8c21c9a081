// SPDX-License-Identifier: MIT
/// @brief Test JPEGs made with TurboJPEG directly (tjCompress2): a seeded, textured RGB image
///        (gradients, stripes, a disc, noise) so that decoding errors show, and header surgery
///        that makes a JPEG claim another size; the reference decode the decoder tests compare with.
#pragma once

#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "xr/video/jpeg_decoder.h"

namespace telesphere::xr::test {

/// A w×h RGB image, rows top first, the same for the same seed.
inline std::vector<std::uint8_t> texturedRgb(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-12, 12);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  const double cx = w * 0.4, cy = h * 0.6, r = std::min(w, h) * 0.25;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * w + x) * 3;
      const bool disc = (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
      const int stripes = ((x / 7 + y / 5 + static_cast<int>(seed)) % 2) * 40;
      const int base[3] = {255 * x / w, 255 * y / h, disc ? 220 : 60};
      for (int c = 0; c < 3; ++c)
        rgb[i + static_cast<std::size_t>(c)] =
            static_cast<std::uint8_t>(std::clamp(base[c] + stripes + noise(rng), 0, 255));
    }
  return rgb;
}

/// tjCompress2 of `rgb` (w×h) at `quality` with TJSAMP_* `subsamp`.
inline std::vector<std::uint8_t> encodeJpeg(const std::vector<std::uint8_t>& rgb, int w, int h,
                                            int subsamp, int quality = 90) {
  tjhandle c = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long size = 0;
  EXPECT_EQ(tjCompress2(c, rgb.data(), w, 0, h, TJPF_RGB, &out, &size, subsamp, quality, 0), 0)
      << tjGetErrorStr2(c);
  std::vector<std::uint8_t> jpeg(out, out + size);
  tjFree(out);
  tjDestroy(c);
  return jpeg;
}

inline std::vector<std::uint8_t> texturedJpeg(int w, int h, std::uint32_t seed,
                                              int subsamp = TJSAMP_420, int quality = 90) {
  return encodeJpeg(texturedRgb(w, h, seed), w, h, subsamp, quality);
}

/// The same JPEG with its SOF0 header claiming width × height (each ≤ 65535).
inline std::vector<std::uint8_t> withHeaderSize(std::vector<std::uint8_t> jpeg, int width, int height) {
  for (std::size_t i = 0; i + 8 < jpeg.size(); ++i) {
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xC0) {  // SOF0: length(2) precision(1) height(2) width(2)
      jpeg[i + 5] = static_cast<std::uint8_t>(height >> 8);
      jpeg[i + 6] = static_cast<std::uint8_t>(height & 0xFF);
      jpeg[i + 7] = static_cast<std::uint8_t>(width >> 8);
      jpeg[i + 8] = static_cast<std::uint8_t>(width & 0xFF);
      return jpeg;
    }
  }
  ADD_FAILURE() << "no SOF0 marker";
  return jpeg;
}

/// `jpeg` decoded by a lone video::JpegDecoder (no size limit below 8192 px): what the pooled and
/// linked decoders must reproduce exactly.
inline render::YuvPlanes referenceDecode(const std::vector<std::uint8_t>& jpeg) {
  video::JpegDecoder decoder;
  render::YuvPlanes planes;
  std::string error;
  EXPECT_EQ(decoder.decode(jpeg, 0, 0, 8192, planes, &error), video::JpegDecodeError::kNone) << error;
  return planes;
}

}  // namespace telesphere::xr::test
