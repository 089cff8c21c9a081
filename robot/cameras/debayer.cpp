// SPDX-License-Identifier: MIT
/// @brief Bilinear demosaicing of 8-bit Bayer mosaics to packed RGB8.
#include "robot/cameras/debayer.h"

namespace telesphere::robot::cameras {
namespace {

inline std::uint8_t debayerMean2(int a, int b) { return static_cast<std::uint8_t>((a + b + 1) >> 1); }
inline std::uint8_t debayerMean4(int a, int b, int c, int d) {
  return static_cast<std::uint8_t>((a + b + c + d + 2) >> 2);
}

/// Rows above, at and below the output row, and where the row's own colour (R in a red row, B in
/// a blue row) and the other one go in the RGB triple.
struct DebayerRow {
  const std::uint8_t* up;
  const std::uint8_t* mid;
  const std::uint8_t* down;
  std::uint8_t* out;
  int row_channel;    // 0 (R) in a red row, 2 (B) in a blue row
  int other_channel;  // 2 − row_channel
};

/// R or B site: G from the 4 edge neighbours, the opposite colour from the 4 diagonals.
inline void debayerColourSite(const DebayerRow& r, int x, int x_left, int x_right) {
  std::uint8_t* p = r.out + static_cast<std::ptrdiff_t>(x) * 3;
  p[r.row_channel] = r.mid[x];
  p[1] = debayerMean4(r.up[x], r.down[x], r.mid[x_left], r.mid[x_right]);
  p[r.other_channel] = debayerMean4(r.up[x_left], r.up[x_right], r.down[x_left], r.down[x_right]);
}

/// G site: the row's colour from left/right, the other colour from up/down.
inline void debayerGreenSite(const DebayerRow& r, int x, int x_left, int x_right) {
  std::uint8_t* p = r.out + static_cast<std::ptrdiff_t>(x) * 3;
  p[r.row_channel] = debayerMean2(r.mid[x_left], r.mid[x_right]);
  p[1] = r.mid[x];
  p[r.other_channel] = debayerMean2(r.up[x], r.down[x]);
}

inline void debayerSite(const DebayerRow& r, bool colour_site, int x, int x_left, int x_right) {
  if (colour_site)
    debayerColourSite(r, x, x_left, x_right);
  else
    debayerGreenSite(r, x, x_left, x_right);
}

}  // namespace

bool checkMosaic(const char* who, const std::uint8_t* src, int width, int height, int src_stride,
                 PixelFormat layout, std::string* error) {
  auto fail = [&](const std::string& message) {
    if (error) *error = std::string(who) + ": " + message;
    return false;
  };
  if (!isBayer(layout)) return fail(std::string(pixelFormatName(layout)) + " is not a Bayer layout");
  if (src == nullptr) return fail("no source pixels");
  if (width < 2 || height < 2)
    return fail("image " + std::to_string(width) + "x" + std::to_string(height) + " is smaller than 2x2");
  if (src_stride < width)
    return fail("stride " + std::to_string(src_stride) + " bytes is less than the width " + std::to_string(width));
  return true;
}

std::vector<std::uint8_t> bayerMosaicOf(const std::uint8_t* rgb, int width, int height, int rgb_stride,
                                        PixelFormat layout) {
  std::vector<std::uint8_t> samples(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      samples[static_cast<std::size_t>(y) * width + x] =
          rgb[static_cast<std::size_t>(y) * rgb_stride + 3 * x + bayerChannelAt(layout, x, y)];
  return samples;
}

bool debayerBilinear(const std::uint8_t* src, int width, int height, int src_stride, PixelFormat layout,
                     std::vector<std::uint8_t>& out_rgb, std::string* error) {
  if (!checkMosaic("debayerBilinear", src, width, height, src_stride, layout, error)) return false;

  const int red_x = redSiteOf(layout).x, red_y = redSiteOf(layout).y;

  out_rgb.resize(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    // Mirror without repeating the edge: row −1 reads row 1, row h reads row h − 2 (same parity).
    const int y_up = y == 0 ? 1 : y - 1;
    const int y_down = y == height - 1 ? height - 2 : y + 1;
    const bool red_row = (y & 1) == red_y;
    const DebayerRow row{src + static_cast<std::ptrdiff_t>(y_up) * src_stride,
                         src + static_cast<std::ptrdiff_t>(y) * src_stride,
                         src + static_cast<std::ptrdiff_t>(y_down) * src_stride,
                         out_rgb.data() + static_cast<std::size_t>(y) * width * 3, red_row ? 0 : 2, red_row ? 2 : 0};
    // In a red row the samples alternate R/G, in a blue row B/G; `colour_x` is where R (or B) sits.
    const int colour_x = red_row ? red_x : 1 - red_x;
    debayerSite(row, colour_x == 0, 0, 1, 1);
    // Interior in pairs (a colour site and a green site, in the row's order): no branches.
    int x = 1;
    if (colour_x == 1) {
      for (; x + 1 < width - 1; x += 2) {
        debayerColourSite(row, x, x - 1, x + 1);
        debayerGreenSite(row, x + 1, x, x + 2);
      }
    } else {
      for (; x + 1 < width - 1; x += 2) {
        debayerGreenSite(row, x, x - 1, x + 1);
        debayerColourSite(row, x + 1, x, x + 2);
      }
    }
    for (; x < width - 1; ++x) debayerSite(row, (x & 1) == colour_x, x, x - 1, x + 1);
    if (width > 1) debayerSite(row, ((width - 1) & 1) == colour_x, width - 1, width - 2, width - 2);
  }
  return true;
}

}  // namespace telesphere::robot::cameras
