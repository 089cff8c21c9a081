// SPDX-License-Identifier: MIT
/// @brief DebayerToYuv420 against a double-precision reference written from the definitions (the
///        GenICam colour-filter layouts, bilinear means of the nearest samples of each colour with
///        mirrored borders, JFIF's RGB → YCbCr on each pixel and on each 2×2 block's mean): every
///        layout, odd and tiny sizes, padded strides, random and extreme content; every Y, Cb and Cr
///        within 0.51 of the reference (rounding plus libjpeg's 16-bit coefficients). Planes keep
///        their memory between frames; non-mosaics and bad sizes are refused. 10-, 12- and 16-bit
///        sensors, narrowed at capture, against the reference of their full samples.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "robot/cameras/debayer_yuv420.h"
#include "robot/cameras/narrow_samples.h"

namespace telesphere::robot {
namespace {

constexpr std::array<cameras::PixelFormat, 4> kLayouts = {cameras::PixelFormat::kBayerRG8, cameras::PixelFormat::kBayerGR8,
                                                          cameras::PixelFormat::kBayerGB8, cameras::PixelFormat::kBayerBG8};

/// The channel (0 R, 1 G, 2 B) sampled at (x, y): the layout's name gives its top-left 2×2 cell.
int channelAt(cameras::PixelFormat layout, int x, int y) {
  const char* cell = layout == cameras::PixelFormat::kBayerRG8   ? "RGGB"
                     : layout == cameras::PixelFormat::kBayerGR8 ? "GRBG"
                     : layout == cameras::PixelFormat::kBayerGB8 ? "GBRG"
                                                                 : "BGGR";
  const char c = cell[(y & 1) * 2 + (x & 1)];
  return c == 'R' ? 0 : c == 'G' ? 1 : 2;
}

struct Reference {
  int w = 0, h = 0;
  std::vector<double> y, u, v;
};

/// Bilinear demosaic in doubles: a pixel keeps its own sample; a missing colour is the mean of
/// that colour's samples among the 4 edge neighbours, or among the 4 diagonal ones when no edge
/// neighbour has it. Borders mirror without repeating the edge (−1 reads 1). Then JFIF YCbCr.
/// `raw` holds the samples on the 0–255 scale (fractions where a wider sensor's samples are scaled).
Reference reference(const std::vector<double>& raw, int w, int h, int stride, cameras::PixelFormat layout) {
  const auto mirror = [](int i, int n) { return i < 0 ? -i : i >= n ? 2 * (n - 1) - i : i; };
  std::vector<std::array<double, 3>> rgb(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        if (channelAt(layout, x, y) == c) {
          rgb[y * w + x][c] = raw[y * stride + x];
          continue;
        }
        for (const auto& ring : {std::array<std::array<int, 2>, 4>{{{-1, 0}, {1, 0}, {0, -1}, {0, 1}}},
                                 std::array<std::array<int, 2>, 4>{{{-1, -1}, {1, -1}, {-1, 1}, {1, 1}}}}) {
          double sum = 0;
          int n = 0;
          for (const auto& [dx, dy] : ring) {
            const int sx = mirror(x + dx, w), sy = mirror(y + dy, h);
            if (channelAt(layout, sx, sy) != c) continue;
            sum += raw[sy * stride + sx];
            ++n;
          }
          if (n > 0) {
            rgb[y * w + x][c] = sum / n;
            break;
          }
        }
      }
  Reference r;
  r.w = w;
  r.h = h;
  for (const auto& p : rgb) r.y.push_back(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]);
  for (int cy = 0; cy < (h + 1) / 2; ++cy)
    for (int cx = 0; cx < (w + 1) / 2; ++cx) {
      std::array<double, 3> mean{};
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)  // an odd edge is replicated, as libjpeg does
          for (int c = 0; c < 3; ++c) mean[c] += rgb[std::min(2 * cy + dy, h - 1) * w + std::min(2 * cx + dx, w - 1)][c] / 4;
      r.u.push_back(-0.168736 * mean[0] - 0.331264 * mean[1] + 0.5 * mean[2] + 128);
      r.v.push_back(0.5 * mean[0] - 0.418688 * mean[1] - 0.081312 * mean[2] + 128);
    }
  return r;
}

Reference reference(const std::vector<std::uint8_t>& raw, int w, int h, int stride, cameras::PixelFormat layout) {
  return reference(std::vector<double>(raw.begin(), raw.end()), w, h, stride, layout);
}

/// Largest |out − reference| over one plane.
double worst(const std::vector<std::uint8_t>& got, const std::vector<double>& want) {
  EXPECT_EQ(got.size(), want.size());
  double d = 0;
  for (std::size_t i = 0; i < std::min(got.size(), want.size()); ++i) d = std::max(d, std::abs(got[i] - want[i]));
  return d;
}

void expectMatchesReference(const std::vector<std::uint8_t>& raw, int w, int h, int stride, cameras::PixelFormat layout) {
  SCOPED_TRACE(std::string(cameras::pixelFormatName(layout)) + " " + std::to_string(w) + "x" + std::to_string(h) +
               " stride " + std::to_string(stride));
  cameras::DebayerToYuv420 debayer;
  cameras::Yuv420Image out;
  std::string error;
  ASSERT_TRUE(debayer.convert(raw.data(), w, h, stride, layout, out, &error)) << error;
  ASSERT_EQ(out.width, w);
  ASSERT_EQ(out.height, h);
  const Reference ref = reference(raw, w, h, stride, layout);
  EXPECT_LE(worst(out.y, ref.y), 0.51);
  EXPECT_LE(worst(out.u, ref.u), 0.51);
  EXPECT_LE(worst(out.v, ref.v), 0.51);
}

std::vector<std::uint8_t> randomMosaic(std::mt19937& rng, int w, int h, int stride) {
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(stride) * h, 0xEE);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) raw[y * stride + x] = static_cast<std::uint8_t>(byte(rng));
  return raw;
}

TEST(DebayerToYuv420, RandomMosaicsOfEveryLayoutAndSizeMatchTheReference) {
  std::mt19937 rng(20261127);
  for (cameras::PixelFormat layout : kLayouts)
    for (auto [w, h, stride] : {std::array{2, 2, 2}, std::array{3, 2, 3}, std::array{2, 3, 5}, std::array{3, 3, 3},
                                std::array{5, 7, 8}, std::array{64, 48, 64}, std::array{67, 35, 80}, std::array{33, 64, 33},
                                // rows long enough for the vector loops of every width (AVX2's 32 bytes) and their tails
                                std::array{517, 9, 523}, std::array{1026, 4, 1026}})
      expectMatchesReference(randomMosaic(rng, w, h, stride), w, h, stride, layout);
}

TEST(DebayerToYuv420, ExtremeContentStaysInRange) {
  // Saturated colours: pure blue's Cb and pure red's Cr are 255.5 exactly (rounded down, never
  // wrapped to 0); black and white; a mosaic alternating 0 and 255 (the largest local contrast).
  for (cameras::PixelFormat layout : kLayouts) {
    for (const std::array<int, 3> colour : {std::array{0, 0, 255}, std::array{255, 0, 0}, std::array{0, 0, 0},
                                            std::array{255, 255, 255}, std::array{0, 255, 0}}) {
      std::vector<std::uint8_t> raw(16 * 10);
      for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 16; ++x) raw[y * 16 + x] = static_cast<std::uint8_t>(colour[channelAt(layout, x, y)]);
      expectMatchesReference(raw, 16, 10, 16, layout);
      cameras::DebayerToYuv420 debayer;
      cameras::Yuv420Image out;
      ASSERT_TRUE(debayer.convert(raw.data(), 16, 10, 16, layout, out, nullptr));
      if (colour == std::array{0, 0, 255}) {
        EXPECT_EQ(out.u[0], 255);
      }
      if (colour == std::array{255, 0, 0}) {
        EXPECT_EQ(out.v[0], 255);
      }
    }
    std::vector<std::uint8_t> checker(31 * 17);
    for (int y = 0; y < 17; ++y)
      for (int x = 0; x < 31; ++x) checker[y * 31 + x] = ((x + y) & 1) ? 255 : 0;
    expectMatchesReference(checker, 31, 17, 31, layout);
  }
}

TEST(DebayerToYuv420, WideSensorsNarrowedAtCaptureMatchTheReferenceOfTheirFullSamples) {
  // A 10-, 12- or 16-bit sensor: AravisCamera narrows its samples to 8 bits (narrowSamplesTo8Bits)
  // before this demosaic. The reference demosaics the full samples scaled to 0–255 without
  // rounding them; narrowing adds at most half a step to each sample, and every Y, Cb and Cr is a
  // combination whose weights' magnitudes sum to at most 1: within 0.51 + 0.5.
  std::mt19937 rng(20261128);
  for (const int bits : {10, 12, 16}) {
    const int max = (1 << bits) - 1;
    std::uniform_int_distribution<int> sample(0, max);
    for (cameras::PixelFormat layout : kLayouts)
      for (auto [w, h, stride16] : {std::array{2, 2, 4}, std::array{7, 5, 14}, std::array{67, 35, 150}, std::array{1026, 4, 2052}}) {
        SCOPED_TRACE(std::to_string(bits) + " bits, " + cameras::pixelFormatName(layout) + " " + std::to_string(w) + "x" +
                     std::to_string(h));
        std::vector<std::uint8_t> wide(static_cast<std::size_t>(stride16) * h, 0xEE);
        std::vector<double> scaled(static_cast<std::size_t>(w) * h);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            // Extremes first (black and full scale), then random values.
            const int v = y == 0 && x < 2 ? (x == 0 ? 0 : max) : sample(rng);
            wide[y * stride16 + 2 * x] = static_cast<std::uint8_t>(v & 0xFF);
            wide[y * stride16 + 2 * x + 1] = static_cast<std::uint8_t>(v >> 8);
            scaled[y * w + x] = v * 255.0 / max;
          }
        std::vector<std::uint8_t> narrow(static_cast<std::size_t>(w) * h);
        std::string error;
        ASSERT_TRUE(cameras::narrowSamplesTo8Bits(wide.data(), w, h, stride16, bits, narrow.data(), w, &error)) << error;
        cameras::DebayerToYuv420 debayer;
        cameras::Yuv420Image out;
        ASSERT_TRUE(debayer.convert(narrow.data(), w, h, w, layout, out, &error)) << error;
        const Reference ref = reference(scaled, w, h, w, layout);
        EXPECT_LE(worst(out.y, ref.y), 1.01);
        EXPECT_LE(worst(out.u, ref.u), 1.01);
        EXPECT_LE(worst(out.v, ref.v), 1.01);
      }
  }
}

TEST(DebayerToYuv420, PlanesKeepTheirMemoryFromFrameToFrame) {
  std::mt19937 rng(7);
  cameras::DebayerToYuv420 debayer;
  cameras::Yuv420Image out;
  const auto first = randomMosaic(rng, 96, 64, 96);
  ASSERT_TRUE(debayer.convert(first.data(), 96, 64, 96, cameras::PixelFormat::kBayerRG8, out, nullptr));
  const auto* y = out.y.data();
  const auto* u = out.u.data();
  const auto* v = out.v.data();
  const auto second = randomMosaic(rng, 96, 64, 96);
  ASSERT_TRUE(debayer.convert(second.data(), 96, 64, 96, cameras::PixelFormat::kBayerRG8, out, nullptr));
  EXPECT_EQ(out.y.data(), y);
  EXPECT_EQ(out.u.data(), u);
  EXPECT_EQ(out.v.data(), v);
  ASSERT_EQ(out.u.size(), 48u * 32u);
  // A smaller frame after a larger one: the same memory, the sizes of the smaller one.
  const auto small = randomMosaic(rng, 33, 21, 40);
  ASSERT_TRUE(debayer.convert(small.data(), 33, 21, 40, cameras::PixelFormat::kBayerGB8, out, nullptr));
  EXPECT_EQ(out.y.data(), y);
  EXPECT_EQ(out.u.size(), 17u * 11u);
}

TEST(DebayerToYuv420, NonMosaicsAndBadSizesAreRefusedWithTheReason) {
  cameras::DebayerToYuv420 debayer;
  cameras::Yuv420Image out;
  std::vector<std::uint8_t> raw(64, 10);
  std::string error;
  EXPECT_FALSE(debayer.convert(raw.data(), 8, 8, 8, cameras::PixelFormat::kMono8, out, &error));
  EXPECT_NE(error.find("Mono8 is not a Bayer layout"), std::string::npos) << error;
  EXPECT_FALSE(debayer.convert(raw.data(), 4, 4, 12, cameras::PixelFormat::kRgb8, out, &error));
  EXPECT_FALSE(debayer.convert(raw.data(), 1, 8, 8, cameras::PixelFormat::kBayerRG8, out, &error));
  EXPECT_NE(error.find("smaller than 2x2"), std::string::npos) << error;
  EXPECT_FALSE(debayer.convert(raw.data(), 8, 8, 4, cameras::PixelFormat::kBayerRG8, out, &error));
  EXPECT_NE(error.find("stride 4 bytes is less than the width 8"), std::string::npos) << error;
  EXPECT_FALSE(debayer.convert(nullptr, 8, 8, 8, cameras::PixelFormat::kBayerRG8, out, &error));
}

}  // namespace
}  // namespace telesphere::robot
