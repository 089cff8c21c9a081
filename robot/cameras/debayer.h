// SPDX-License-Identifier: MIT
/// @brief Bilinear demosaicing of 8-bit Bayer mosaics (RG, GR, GB, BG) to packed RGB8, the
///        conversion AravisCamera applies where the camera delivers raw Bayer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot/cameras/camera_source.h"

namespace telesphere::robot::cameras {

/// True for the four 8-bit Bayer layouts.
constexpr bool isBayer(PixelFormat format) {
  return format == PixelFormat::kBayerRG8 || format == PixelFormat::kBayerGR8 ||
         format == PixelFormat::kBayerGB8 || format == PixelFormat::kBayerBG8;
}

/// Where a Bayer layout's red sample sits in its 2×2 cell (column x, row y; 0 or 1): BayerRG8
/// (0, 0), BayerGR8 (1, 0), BayerGB8 (0, 1), BayerBG8 (1, 1). Blue sits diagonally opposite.
struct BayerRedSite {
  int x = 0, y = 0;
};
constexpr BayerRedSite redSiteOf(PixelFormat layout) {
  return {(layout == PixelFormat::kBayerGR8 || layout == PixelFormat::kBayerBG8) ? 1 : 0,
          (layout == PixelFormat::kBayerGB8 || layout == PixelFormat::kBayerBG8) ? 1 : 0};
}

/// The colour a Bayer layout samples at pixel (x, y): 0 red, 1 green, 2 blue.
constexpr int bayerChannelAt(PixelFormat layout, int x, int y) {
  const BayerRedSite red = redSiteOf(layout);
  const bool red_column = (x & 1) == red.x, red_row = (y & 1) == red.y;
  return red_column && red_row ? 0 : (!red_column && !red_row ? 2 : 1);
}

/// The checks every demosaic makes of its input: a Bayer layout, pixels, at least one 2×2 cell,
/// rows at least `width` bytes apart. False with "<who>: <reason>" in *error (when given).
bool checkMosaic(const char* who, const std::uint8_t* src, int width, int height, int src_stride,
                 PixelFormat layout, std::string* error);

/// What a sensor with this colour filter records of an RGB8 image (rows `rgb_stride` bytes
/// apart): each pixel's sample of its filter's colour, rows `width` bytes apart. For benchmarks
/// and tests that feed the Bayer path from rendered images.
std::vector<std::uint8_t> bayerMosaicOf(const std::uint8_t* rgb, int width, int height, int rgb_stride,
                                        PixelFormat layout);

/// Bilinear demosaic of one 8-bit Bayer image into packed RGB8 (stride width·3, no padding).
///
/// `layout` names the colours of the top-left 2×2 cell (BayerRG8: R at (0,0), G at (1,0) and
/// (0,1), B at (1,1)). At each pixel the sampled colour is kept; a missing colour is the mean of
/// its nearest samples: the 4 edge neighbours (G at R/B sites), the 4 diagonal neighbours (B at
/// R sites, R at B sites) or the 2 neighbours in the row or the column (R and B at G sites),
/// rounded to nearest. Borders mirror without repeating the edge pixel (x = −1 reads x = 1), which
/// keeps the mosaic's parity, so a uniform colour stays exact up to the border and a linear ramp is
/// exact everywhere but the outermost row and column.
///
/// `src`: width·height samples, rows `src_stride` bytes apart (≥ width). width, height ≥ 2.
/// `out_rgb` is resized to width·height·3. Mono8 and RGB8 are not mosaics: false with *error set.
bool debayerBilinear(const std::uint8_t* src, int width, int height, int src_stride, PixelFormat layout,
                     std::vector<std::uint8_t>& out_rgb, std::string* error);

}  // namespace telesphere::robot::cameras
