// SPDX-License-Identifier: MIT
/// @brief boxDownscale against the block means computed directly: rounding to nearest, a stride
///        wider than the row, partial blocks dropped, factor 1 a copy, extremes 0 and 255.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "xr/depth/box_downscale.h"

namespace telesphere::xr::depth {
namespace {

TEST(BoxDownscale, EachPixelIsItsBlocksRoundedMean) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> grey(0, 255);
  const int width = 37, height = 22, stride = 41;  // 4 × 4 blocks: 9 × 5, the rest dropped
  std::vector<std::uint8_t> plane(static_cast<std::size_t>(stride) * height, 7);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) plane[static_cast<std::size_t>(y) * stride + x] = static_cast<std::uint8_t>(grey(rng));
  std::vector<std::uint8_t> out;
  int w = 0, h = 0;
  boxDownscale(plane, width, height, stride, 4, out, &w, &h);
  ASSERT_EQ(w, 9);
  ASSERT_EQ(h, 5);
  ASSERT_EQ(out.size(), 45u);
  for (int by = 0; by < h; ++by)
    for (int bx = 0; bx < w; ++bx) {
      double sum = 0;
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) sum += plane[static_cast<std::size_t>(by * 4 + y) * stride + bx * 4 + x];
      EXPECT_EQ(out[static_cast<std::size_t>(by) * w + bx], static_cast<int>(std::floor(sum / 16 + 0.5))) << bx << "," << by;
    }
}

TEST(BoxDownscale, FactorOneCopiesAndExtremesStay) {
  std::vector<std::uint8_t> plane = {0, 255, 255, 0, 128, 3};
  std::vector<std::uint8_t> out;
  int w = 0, h = 0;
  boxDownscale(plane, 3, 2, 3, 1, out, &w, &h);
  EXPECT_EQ(out, plane);
  const std::vector<std::uint8_t> white(64, 255), black(64, 0);
  boxDownscale(white, 8, 8, 8, 8, out, &w, &h);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], 255);
  boxDownscale(black, 8, 8, 8, 8, out, &w, &h);
  EXPECT_EQ(out[0], 0);
  boxDownscale(black, 8, 8, 8, 9, out, &w, &h);  // a block larger than the image: nothing
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(w, 0);
}

}  // namespace
}  // namespace telesphere::xr::depth
