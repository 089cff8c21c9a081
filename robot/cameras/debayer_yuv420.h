// SPDX-License-Identifier: MIT
/// @brief Bilinear demosaicing of an 8-bit Bayer mosaic straight into YUV 4:2:0 planes (#34): the
///        same interpolation as debayerBilinear (robot/cameras/debayer.h), carried in integers four
///        times the sample scale so nothing is rounded before the colour conversion, then JPEG's
///        RGB → YCbCr (JFIF, BT.601 full range) per pixel for Y and on the mean of each 2×2 block
///        for Cb and Cr. No RGB image is made and, once the sizes are known, nothing is allocated.
///        Speed: each row is split into its even and odd columns first, so every pass is a
///        contiguous loop the compiler vectorises (on x86-64 in an AVX2 and an SSE2 version, picked
///        at start); a 4K image takes 4–5 ms of one core here with AVX2, 6.5–7 ms with SSE2 alone
///        (`telesphere-bench codec`).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot/cameras/camera_source.h"
#include "robot/cameras/yuv420_image.h"

namespace telesphere::robot::cameras {

class DebayerToYuv420 {
 public:
  /// Converts one image (`layout` one of the four Bayer layouts; rows `src_stride` bytes apart,
  /// ≥ width; width, height ≥ 2) into `out` (resized, memory kept between calls). Each output
  /// value is the exact value rounded to nearest up to the 16-bit fixed-point colour
  /// coefficients: within 1 of a double-precision reference. Borders mirror as debayerBilinear
  /// does; an odd last column or row counts its own pixels once in the chroma mean (the edge
  /// replicated, as libjpeg does when it downsamples). False with *error set on bad input.
  bool convert(const std::uint8_t* src, int width, int height, int src_stride, PixelFormat layout,
               Yuv420Image& out, std::string* error);

 private:
  /// One source row split into its even and odd columns, with the mirrored border columns as
  /// guards: at(even, i) is column 2i for i in [−1, n], at(odd, i) column 2i + 1.
  struct SplitRow {
    std::vector<std::uint16_t> even, odd;
  };
  /// One demosaiced row at 4× scale, even and odd columns apart (≤ 1 020, so 16 bits hold them):
  /// the loops over it are contiguous and vectorise.
  struct Rgb4Row {
    std::vector<std::uint16_t> r_even, r_odd, g_even, g_odd, b_even, b_odd;
  };
  void split(const std::uint8_t* row, int width, SplitRow& out) const;
  void demosaicRow(const SplitRow& up, const SplitRow& mid, const SplitRow& down, int width, bool red_row,
                   int colour_parity, Rgb4Row& out) const;
  SplitRow split_[4];  ///< the rows above, at, below the two rows of one chroma row (scratch)
  Rgb4Row rows_[2];    ///< the two rows of one chroma row (scratch, kept between frames)
  std::vector<std::int16_t> sums_[3];  ///< R, G, B summed over each 2×2 block of them
};

}  // namespace telesphere::robot::cameras
