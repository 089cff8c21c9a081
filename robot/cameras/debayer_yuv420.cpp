// SPDX-License-Identifier: MIT
/// @brief Bilinear demosaicing of 8-bit Bayer mosaics straight into YUV 4:2:0 planes.
#include "robot/cameras/debayer_yuv420.h"

#include <algorithm>
#include <cstddef>

#include "robot/cameras/debayer.h"

namespace telesphere::robot::cameras {
namespace {

// JPEG's RGB → YCbCr (JFIF) with libjpeg's 16-bit coefficients (jccolor.c), Y from one pixel at 4×
// the sample scale (shift 16 + 2), Cb and Cr from the sum of a 2×2 block at 4× (shift 16 + 4).
constexpr std::int32_t kYr = 19595, kYg = 38470, kYb = 7471;          // 0.299, 0.587, 0.114
constexpr std::int32_t kCbR = -11059, kCbG = -21709, kCbB = 32768;    // −0.16874, −0.33126, 0.5
constexpr std::int32_t kCrR = 32768, kCrG = -27439, kCrB = -5329;     // 0.5, −0.41869, −0.08131
// Chroma rounds half down, as libjpeg does, so 255.5 (pure blue's Cb) stays 255.
constexpr std::int32_t kChromaOffset = (128 << 20) + (1 << 19) - 1;

/// The row being demosaiced: rows above, at and below it, and where its own colour (R in a red
/// row, B in a blue row) and the other one go.
struct SiteRow {
  const std::uint8_t* up;
  const std::uint8_t* mid;
  const std::uint8_t* down;
  std::int16_t* own;    // R in a red row, B in a blue row
  std::int16_t* green;
  std::int16_t* other;  // the opposite colour
};

/// R or B site: G from the 4 edge neighbours, the opposite colour from the 4 diagonals (4× scale).
inline void colourSite(const SiteRow& r, int x, int x_left, int x_right) {
  r.own[x] = static_cast<std::int16_t>(4 * r.mid[x]);
  r.green[x] = static_cast<std::int16_t>(r.up[x] + r.down[x] + r.mid[x_left] + r.mid[x_right]);
  r.other[x] = static_cast<std::int16_t>(r.up[x_left] + r.up[x_right] + r.down[x_left] + r.down[x_right]);
}

/// G site: the row's colour from left and right, the other colour from up and down (4× scale).
inline void greenSite(const SiteRow& r, int x, int x_left, int x_right) {
  r.own[x] = static_cast<std::int16_t>(2 * (r.mid[x_left] + r.mid[x_right]));
  r.green[x] = static_cast<std::int16_t>(4 * r.mid[x]);
  r.other[x] = static_cast<std::int16_t>(2 * (r.up[x] + r.down[x]));
}

inline void site(const SiteRow& r, bool colour, int x, int x_left, int x_right) {
  if (colour)
    colourSite(r, x, x_left, x_right);
  else
    greenSite(r, x, x_left, x_right);
}

}  // namespace

void DebayerToYuv420::demosaicRow(const std::uint8_t* src, int width, int height, int src_stride, int y,
                                  int red_x, int red_y, Row4& out) const {
  // Mirror without repeating the edge (row −1 reads row 1), as debayerBilinear does.
  const int y_up = y == 0 ? 1 : y - 1;
  const int y_down = y == height - 1 ? height - 2 : y + 1;
  const bool red_row = (y & 1) == red_y;
  const SiteRow row{src + static_cast<std::ptrdiff_t>(y_up) * src_stride,
                    src + static_cast<std::ptrdiff_t>(y) * src_stride,
                    src + static_cast<std::ptrdiff_t>(y_down) * src_stride,
                    red_row ? out.r.data() : out.b.data(), out.g.data(), red_row ? out.b.data() : out.r.data()};
  const int colour_x = red_row ? red_x : 1 - red_x;  // where this row's R (or B) samples sit
  site(row, colour_x == 0, 0, 1, 1);
  int x = 1;
  if (colour_x == 1) {
    for (; x + 1 < width - 1; x += 2) {
      colourSite(row, x, x - 1, x + 1);
      greenSite(row, x + 1, x, x + 2);
    }
  } else {
    for (; x + 1 < width - 1; x += 2) {
      greenSite(row, x, x - 1, x + 1);
      colourSite(row, x + 1, x, x + 2);
    }
  }
  for (; x < width - 1; ++x) site(row, (x & 1) == colour_x, x, x - 1, x + 1);
  site(row, ((width - 1) & 1) == colour_x, width - 1, width - 2, width - 2);
}

bool DebayerToYuv420::convert(const std::uint8_t* src, int width, int height, int src_stride, PixelFormat layout,
                              Yuv420Image& out, std::string* error) {
  auto fail = [&](const std::string& message) {
    if (error) *error = "DebayerToYuv420: " + message;
    return false;
  };
  if (!isBayer(layout)) return fail(std::string(pixelFormatName(layout)) + " is not a Bayer layout");
  if (src == nullptr) return fail("no source pixels");
  if (width < 2 || height < 2)
    return fail("image " + std::to_string(width) + "x" + std::to_string(height) + " is smaller than 2x2");
  if (src_stride < width)
    return fail("stride " + std::to_string(src_stride) + " bytes is less than the width " + std::to_string(width));

  const int red_x = (layout == PixelFormat::kBayerGR8 || layout == PixelFormat::kBayerBG8) ? 1 : 0;
  const int red_y = (layout == PixelFormat::kBayerGB8 || layout == PixelFormat::kBayerBG8) ? 1 : 0;
  out.resize(width, height);
  for (Row4& row : rows_) {
    row.r.resize(static_cast<std::size_t>(width));
    row.g.resize(static_cast<std::size_t>(width));
    row.b.resize(static_cast<std::size_t>(width));
  }
  const int chroma_width = out.chromaWidth();
  for (int cy = 0; cy < out.chromaHeight(); ++cy) {
    const int y0 = 2 * cy;
    const bool two_rows = y0 + 1 < height;  // else the last row counts twice (edge replicated)
    demosaicRow(src, width, height, src_stride, y0, red_x, red_y, rows_[0]);
    if (two_rows) demosaicRow(src, width, height, src_stride, y0 + 1, red_x, red_y, rows_[1]);
    const Row4& a = rows_[0];
    const Row4& b = two_rows ? rows_[1] : rows_[0];
    for (int i = 0; i < (two_rows ? 2 : 1); ++i) {
      const Row4& row = rows_[i];
      std::uint8_t* luma = out.y.data() + static_cast<std::size_t>(y0 + i) * width;
      for (int x = 0; x < width; ++x)
        luma[x] = static_cast<std::uint8_t>((kYr * row.r[x] + kYg * row.g[x] + kYb * row.b[x] + (1 << 17)) >> 18);
    }
    std::uint8_t* cb = out.u.data() + static_cast<std::size_t>(cy) * chroma_width;
    std::uint8_t* cr = out.v.data() + static_cast<std::size_t>(cy) * chroma_width;
    for (int cx = 0; cx < chroma_width; ++cx) {
      const int x0 = 2 * cx;
      const int x1 = std::min(x0 + 1, width - 1);  // an odd last column counts twice
      const std::int32_t sr = a.r[x0] + a.r[x1] + b.r[x0] + b.r[x1];
      const std::int32_t sg = a.g[x0] + a.g[x1] + b.g[x0] + b.g[x1];
      const std::int32_t sb = a.b[x0] + a.b[x1] + b.b[x0] + b.b[x1];
      cb[cx] = static_cast<std::uint8_t>((kCbR * sr + kCbG * sg + kCbB * sb + kChromaOffset) >> 20);
      cr[cx] = static_cast<std::uint8_t>((kCrR * sr + kCrG * sg + kCrB * sb + kChromaOffset) >> 20);
    }
  }
  return true;
}

}  // namespace telesphere::robot::cameras
