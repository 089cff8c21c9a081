// SPDX-License-Identifier: MIT
/// @brief Bilinear demosaicing of an 8-bit Bayer mosaic straight into YUV 4:2:0 planes (#34): the
///        same interpolation as debayerBilinear (robot/cameras/debayer.h), carried in integers four
///        times the sample scale so nothing is rounded before the colour conversion, then JPEG's
///        RGB → YCbCr (JFIF, BT.601 full range) per pixel for Y and on the mean of each 2×2 block
///        for Cb and Cr. No RGB image is made and, once the sizes are known, nothing is allocated.
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
  /// One demosaiced row at 4× scale: R, G, B at each pixel (≤ 1 020, so 16 bits hold them).
  struct Row4 {
    std::vector<std::int16_t> r, g, b;
  };
  void demosaicRow(const std::uint8_t* src, int width, int height, int src_stride, int y, int red_x,
                   int red_y, Row4& out) const;
  Row4 rows_[2];  ///< the two rows of one chroma row (scratch, kept between frames)
};

}  // namespace telesphere::robot::cameras
