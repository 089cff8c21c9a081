// SPDX-License-Identifier: MIT
/// @brief BilinearTap (xr/depth/bilinear_tap.h) against a double-precision bilinear reference:
///        seeded random positions over a random image, the image's last row and column and its
///        corners, a 2 × 2 image; the error stays within what quantising the position to 1/256
///        px allows (half a step times the steepest neighbouring difference, ≤ 255/512 grey).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <utility>
#include <random>
#include <vector>

#include "xr/depth/bilinear_tap.h"

namespace telesphere::xr::depth {
namespace {

double referenceBilinear(const std::vector<std::uint8_t>& image, int width, int height, double x, double y) {
  const int x0 = std::min(static_cast<int>(std::floor(x)), width - 2), y0 = std::min(static_cast<int>(std::floor(y)), height - 2);
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int c, int r) { return static_cast<double>(image[static_cast<std::size_t>(r) * width + c]); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

/// The most a 1/512 px shift can move the bilinear value near (x, y): half a weight step times the
/// steepest difference of the block's pixels, plus float rounding.
double bound(const std::vector<std::uint8_t>& image, int width, int height, double x, double y) {
  const int x0 = std::min(static_cast<int>(std::floor(x)), width - 2), y0 = std::min(static_cast<int>(std::floor(y)), height - 2);
  const auto at = [&](int c, int r) { return static_cast<double>(image[static_cast<std::size_t>(r) * width + c]); };
  const double steepest = std::max({std::abs(at(x0 + 1, y0) - at(x0, y0)), std::abs(at(x0 + 1, y0 + 1) - at(x0, y0 + 1)),
                                    std::abs(at(x0, y0 + 1) - at(x0, y0)), std::abs(at(x0 + 1, y0 + 1) - at(x0 + 1, y0))});
  return 2.0 * steepest / 512.0 + 1e-3;
}

TEST(BilinearTap, MatchesTheDoubleBilinearWithinItsQuantisationEverywhere) {
  std::mt19937 rng(35);
  for (const auto& [width, height] : {std::pair{2, 2}, std::pair{97, 61}, std::pair{480, 270}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height));
    std::vector<std::uint8_t> image(static_cast<std::size_t>(width) * height);
    std::uniform_int_distribution<int> grey(0, 255);
    for (auto& v : image) v = static_cast<std::uint8_t>(grey(rng));
    std::vector<Eigen::Vector2d> points;
    std::uniform_real_distribution<double> ux(0.0, width - 1.0), uy(0.0, height - 1.0);
    for (int i = 0; i < 2000; ++i) points.emplace_back(ux(rng), uy(rng));
    // The far edges and corners: the 2×2 block is the last one, its weight 1 (256/256).
    for (double x : {0.0, 0.5, width - 1.5, width - 1.0})
      for (double y : {0.0, height - 1.0, (height - 1.0) / 2.0}) points.emplace_back(x, y);
    double worst = 0;
    for (const Eigen::Vector2d& p : points) {
      const BilinearTap tap = bilinearTap(p, width, height);
      ASSERT_LE(tap.x + 1, width - 1);
      ASSERT_LE(tap.y + 1, height - 1);
      ASSERT_LE(tap.wx, 256);
      ASSERT_LE(tap.wy, 256);
      const double got = tapGrey(image.data(), width, tap), want = referenceBilinear(image, width, height, p.x(), p.y());
      ASSERT_LE(std::abs(got - want), bound(image, width, height, p.x(), p.y())) << p.transpose();
      worst = std::max(worst, std::abs(got - want));
    }
    EXPECT_LE(worst, 255.0 / 256.0 + 1e-3);
  }
}

TEST(BilinearTap, PixelCentresAreExactAndRowsFollowTheStride) {
  // A 3 × 2 image inside rows of 8 bytes: the padding is never read for a position inside.
  const std::vector<std::uint8_t> padded = {10, 20, 30, 99, 99, 99, 99, 99,  //
                                            40, 50, 60, 99, 99, 99, 99, 99};
  EXPECT_FLOAT_EQ(tapGrey(padded.data(), 8, bilinearTap({0, 0}, 3, 2)), 10.0F);
  EXPECT_FLOAT_EQ(tapGrey(padded.data(), 8, bilinearTap({2, 1}, 3, 2)), 60.0F);
  EXPECT_FLOAT_EQ(tapGrey(padded.data(), 8, bilinearTap({2, 0}, 3, 2)), 30.0F);
  EXPECT_FLOAT_EQ(tapGrey(padded.data(), 8, bilinearTap({1.5, 0.5}, 3, 2)), 40.0F);  // (20 + 30 + 50 + 60) / 4
}

TEST(BilinearTap, WeightsRoundAsLroundAtEveryHalfStepAndBesideIt) {
  // The weights as std::lround((p − floor p) · 256) gives them, at positions where a fraction lies
  // at a half step of 1/256 or one double ulp beside it, and at (0.5 − 2⁻⁵⁴) / 256, where adding ½
  // before truncating would round up.
  const int width = 480, height = 270;
  std::vector<double> positions = {std::ldexp(0.5 - std::ldexp(1.0, -54), -8)};
  for (const double pixel : {0.0, 1.0, 17.0, 478.0})
    for (int step = 0; step < 256; step += 5) {
      const double half = pixel + (step + 0.5) / 256.0;
      positions.insert(positions.end(), {half, std::nextafter(half, 0.0), std::nextafter(half, 1e9)});
    }
  positions.insert(positions.end(), {width - 1.0, std::nextafter(width - 1.0, 0.0), 0.0});
  for (const double p : positions) {
    const BilinearTap tap = bilinearTap({p, p / 2.0}, width, height);
    const auto expected = [](double v, int size) {
      const int v0 = std::min(static_cast<int>(std::floor(v)), size - 2);
      return std::pair{v0, static_cast<int>(std::clamp(std::lround((v - v0) * 256.0), 0L, 256L))};
    };
    const auto [x0, wx] = expected(p, width);
    const auto [y0, wy] = expected(p / 2.0, height);
    ASSERT_EQ(tap.x, x0) << std::setprecision(20) << p;
    ASSERT_EQ(tap.wx, wx) << std::setprecision(20) << p;
    ASSERT_EQ(tap.y, y0) << std::setprecision(20) << p / 2.0;
    ASSERT_EQ(tap.wy, wy) << std::setprecision(20) << p / 2.0;
  }
}

}  // namespace
}  // namespace telesphere::xr::depth
