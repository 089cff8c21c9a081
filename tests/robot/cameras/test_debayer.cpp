// SPDX-License-Identifier: MIT
/// @brief debayerBilinear: every Bayer layout on known colour patterns (uniform colours, colour
///        bars, linear ramps), exact where bilinear interpolation is exact; odd sizes, padded
///        strides, and refusal of non-mosaics and bad sizes.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>

#include "robot/cameras/debayer.h"

namespace telesphere::robot {
namespace {

using Rgb = std::array<int, 3>;

constexpr std::array<cameras::PixelFormat, 4> kLayouts = {cameras::PixelFormat::kBayerRG8, cameras::PixelFormat::kBayerGR8,
                                                 cameras::PixelFormat::kBayerGB8, cameras::PixelFormat::kBayerBG8};

/// Which channel (0 R, 1 G, 2 B) the mosaic samples at (x, y): written out per layout from the
/// GenICam definition (names give the top-left 2×2 cell row by row), independent of the code under test.
int sampledChannel(cameras::PixelFormat layout, int x, int y) {
  const char* cell = "";  // top-left, top-right, bottom-left, bottom-right
  switch (layout) {
    case cameras::PixelFormat::kBayerRG8: cell = "RGGB"; break;
    case cameras::PixelFormat::kBayerGR8: cell = "GRBG"; break;
    case cameras::PixelFormat::kBayerGB8: cell = "GBRG"; break;
    case cameras::PixelFormat::kBayerBG8: cell = "BGGR"; break;
    default: ADD_FAILURE() << "not a Bayer layout";
  }
  const char c = cell[(y & 1) * 2 + (x & 1)];
  return c == 'R' ? 0 : c == 'G' ? 1 : 2;
}

/// RG and BG have G on the anti-diagonal of the cell; GR and GB on the main diagonal.
bool isBayerWithGreenOnDiagonal(cameras::PixelFormat layout) {
  return layout == cameras::PixelFormat::kBayerGR8 || layout == cameras::PixelFormat::kBayerGB8;
}

/// Samples an RGB image (function of x, y) through the colour filter array of `layout`.
template <typename Image>
std::vector<std::uint8_t> mosaic(cameras::PixelFormat layout, int w, int h, int stride, Image image) {
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(stride) * h, 0xEE);  // padding: junk
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) raw[y * stride + x] = static_cast<std::uint8_t>(image(x, y)[sampledChannel(layout, x, y)]);
  return raw;
}

Rgb at(const std::vector<std::uint8_t>& rgb, int w, int x, int y) {
  const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
  return {p[0], p[1], p[2]};
}

TEST(Debayer, UniformColourIsExactEverywhereForEveryLayout) {
  const Rgb colour = {200, 100, 30};
  for (cameras::PixelFormat layout : kLayouts)
    for (auto [w, h, stride] : {std::array{8, 6, 8}, std::array{7, 5, 7}, std::array{9, 4, 16}, std::array{2, 2, 2}}) {
      const auto raw = mosaic(layout, w, h, stride, [&](int, int) { return colour; });
      std::vector<std::uint8_t> rgb;
      std::string error;
      ASSERT_TRUE(cameras::debayerBilinear(raw.data(), w, h, stride, layout, rgb, &error)) << error;
      ASSERT_EQ(rgb.size(), static_cast<std::size_t>(w) * h * 3);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_EQ(at(rgb, w, x, y), colour) << cameras::pixelFormatName(layout) << " " << w << "x" << h << " at " << x << "," << y;
    }
}

TEST(Debayer, EachLayoutRecoversPrimaryColoursOnlyWithItsOwnLayout) {
  // A pure red, green and blue image, mosaiced with one layout and decoded with each: only the
  // right layout gives every colour back (so the four layouts are told apart).
  for (cameras::PixelFormat truth : kLayouts)
    for (const Rgb colour : {Rgb{255, 0, 0}, Rgb{0, 255, 0}, Rgb{0, 0, 255}}) {
      const int w = 6, h = 4;
      const auto raw = mosaic(truth, w, h, w, [&](int, int) { return colour; });
      for (cameras::PixelFormat decode : kLayouts) {
        std::vector<std::uint8_t> rgb;
        ASSERT_TRUE(cameras::debayerBilinear(raw.data(), w, h, w, decode, rgb, nullptr));
        const Rgb centre = at(rgb, w, 2, 2);
        // Each layout puts R (and B) at a different place of the 2×2 cell, so red and blue come
        // back only through the right layout; green also through the layout with the same G sites.
        const bool same_green_sites = (decode == truth) ||
                                      (isBayerWithGreenOnDiagonal(decode) == isBayerWithGreenOnDiagonal(truth));
        if (decode == truth || (colour[1] == 255 && same_green_sites)) {
          EXPECT_EQ(centre, colour) << cameras::pixelFormatName(truth) << " decoded as " << cameras::pixelFormatName(decode);
        } else {
          EXPECT_NE(centre, colour) << cameras::pixelFormatName(truth) << " decoded as " << cameras::pixelFormatName(decode);
        }
      }
    }
}

TEST(Debayer, ColourBarsAreExactAwayFromTheirEdges) {
  // Eight 4-px wide bars (black, white, primaries, secondaries): pixels whose 3×3 neighbourhood lies
  // inside one bar are exact; the edges between bars blend within the neighbours' range.
  const std::array<Rgb, 8> bars = {Rgb{0, 0, 0},   Rgb{255, 255, 255}, Rgb{255, 0, 0}, Rgb{0, 255, 0},
                                   Rgb{0, 0, 255}, Rgb{255, 255, 0},   Rgb{0, 255, 255}, Rgb{255, 0, 255}};
  const int w = 32, h = 10;
  auto image = [&](int x, int) { return bars[x / 4]; };
  for (cameras::PixelFormat layout : kLayouts) {
    const auto raw = mosaic(layout, w, h, w, image);
    std::vector<std::uint8_t> rgb;
    ASSERT_TRUE(cameras::debayerBilinear(raw.data(), w, h, w, layout, rgb, nullptr));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool inside = (x % 4 != 0 || x == 0) && (x % 4 != 3 || x == w - 1);
        if (!inside) continue;
        ASSERT_EQ(at(rgb, w, x, y), image(x, y)) << cameras::pixelFormatName(layout) << " at " << x << "," << y;
      }
  }
}

TEST(Debayer, LinearRampIsExactInsideAndWithinOnePixelStepAtTheBorder) {
  const int w = 32, h = 24;
  auto image = [](int x, int y) { return Rgb{2 * x + 3 * y + 10, x + 2 * y + 40, 3 * x + y + 5}; };
  for (cameras::PixelFormat layout : kLayouts) {
    const int stride = w + 3;
    const auto raw = mosaic(layout, w, h, stride, image);
    std::vector<std::uint8_t> rgb;
    ASSERT_TRUE(cameras::debayerBilinear(raw.data(), w, h, stride, layout, rgb, nullptr));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Rgb got = at(rgb, w, x, y), want = image(x, y);
        const bool border = x == 0 || y == 0 || x == w - 1 || y == h - 1;
        for (int c = 0; c < 3; ++c) {
          if (border) {
            ASSERT_LE(std::abs(got[c] - want[c]), 5) << cameras::pixelFormatName(layout) << " at " << x << "," << y << " c" << c;
          } else {
            ASSERT_EQ(got[c], want[c]) << cameras::pixelFormatName(layout) << " at " << x << "," << y << " c" << c;
          }
        }
      }
  }
}

TEST(Debayer, RefusesNonMosaicsAndBadSizes) {
  std::vector<std::uint8_t> raw(64, 0), rgb;
  std::string error;
  EXPECT_FALSE(cameras::debayerBilinear(raw.data(), 8, 8, 8, cameras::PixelFormat::kMono8, rgb, &error));
  EXPECT_NE(error.find("Mono8"), std::string::npos) << error;
  EXPECT_FALSE(cameras::debayerBilinear(raw.data(), 8, 8, 8, cameras::PixelFormat::kRgb8, rgb, &error));
  EXPECT_FALSE(cameras::debayerBilinear(raw.data(), 1, 8, 8, cameras::PixelFormat::kBayerRG8, rgb, &error));
  EXPECT_NE(error.find("1x8"), std::string::npos) << error;
  EXPECT_FALSE(cameras::debayerBilinear(raw.data(), 8, 8, 4, cameras::PixelFormat::kBayerRG8, rgb, &error));
  EXPECT_NE(error.find("stride"), std::string::npos) << error;
  EXPECT_FALSE(cameras::debayerBilinear(nullptr, 8, 8, 8, cameras::PixelFormat::kBayerRG8, rgb, &error));
}

}  // namespace
}  // namespace telesphere::robot
