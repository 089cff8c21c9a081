// SPDX-License-Identifier: MIT
/// @brief narrowSamplesTo8Bits against round(v · 255 / (2^bits − 1)) computed in doubles, for every
///        16-bit word at every width 9–16 (values above the width's maximum clamp to 255);
///        strides with padding on both sides left alone; odd sizes; bad arguments refused with
///        the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "robot/cameras/narrow_samples.h"

namespace telesphere::robot {
namespace {

/// The definition, written independently of the code: nearest 8-bit value of v on 0–255.
int expected(int v, int bits) {
  const int max = (1 << bits) - 1;
  if (v >= max) return 255;
  return static_cast<int>(std::floor(v * 255.0 / max + 0.5));
}

TEST(NarrowSamples, EveryWordAtEveryWidthEqualsTheRoundedScaledValue) {
  // One row of all 65 536 words, little-endian.
  std::vector<std::uint8_t> words(2 * 65536);
  for (int v = 0; v < 65536; ++v) {
    words[2 * v] = static_cast<std::uint8_t>(v & 0xFF);
    words[2 * v + 1] = static_cast<std::uint8_t>(v >> 8);
  }
  for (int bits = cameras::kMinWideSampleBits; bits <= cameras::kMaxWideSampleBits; ++bits) {
    std::vector<std::uint8_t> out(65536);
    std::string error;
    ASSERT_TRUE(cameras::narrowSamplesTo8Bits(words.data(), 65536, 1, 2 * 65536, bits, out.data(), 65536, &error)) << error;
    int mismatches = 0;
    for (int v = 0; v < 65536; ++v) {
      const int want = expected(v, bits);
      if (out[v] != want && ++mismatches <= 5) ADD_FAILURE() << bits << " bits: " << v << " gave " << int{out[v]} << ", want " << want;
      if (cameras::narrowSampleTo8Bits(static_cast<std::uint16_t>(v), bits) != want && ++mismatches <= 5)
        ADD_FAILURE() << bits << " bits, scalar: " << v << ", want " << want;
    }
    EXPECT_EQ(mismatches, 0) << bits << " bits";
    // The ends of the range: black stays 0, full scale is 255, one step above black rounds as it should.
    EXPECT_EQ(out[0], 0);
    EXPECT_EQ(out[(1 << bits) - 1], 255);
  }
}

TEST(NarrowSamples, PaddedRowsAndOddSizesTouchOnlyTheImage) {
  const int w = 5, h = 3, src_stride = 2 * w + 6, dst_stride = w + 3;
  std::vector<std::uint8_t> src(static_cast<std::size_t>(src_stride) * h, 0xFF);  // padding: full-scale junk
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int v = 4095 * (y * w + x) / (w * h - 1);  // 12-bit ramp, 0 to 4095
      src[y * src_stride + 2 * x] = static_cast<std::uint8_t>(v & 0xFF);
      src[y * src_stride + 2 * x + 1] = static_cast<std::uint8_t>(v >> 8);
    }
  std::vector<std::uint8_t> dst(static_cast<std::size_t>(dst_stride) * h, 0xAB);
  std::string error;
  ASSERT_TRUE(cameras::narrowSamplesTo8Bits(src.data(), w, h, src_stride, 12, dst.data(), dst_stride, &error)) << error;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < dst_stride; ++x) {
      if (x >= w) {
        EXPECT_EQ(dst[y * dst_stride + x], 0xAB) << "padding written at " << x << "," << y;
        continue;
      }
      const int v = 4095 * (y * w + x) / (w * h - 1);
      EXPECT_EQ(dst[y * dst_stride + x], expected(v, 12)) << x << "," << y;
    }
  EXPECT_EQ(dst[0], 0);
  EXPECT_EQ(dst[(h - 1) * dst_stride + w - 1], 255);
}

TEST(NarrowSamples, BadArgumentsAreRefusedWithTheReason) {
  std::vector<std::uint8_t> src(64, 0), dst(64, 0);
  std::string error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(src.data(), 4, 4, 8, 8, dst.data(), 4, &error));
  EXPECT_NE(error.find("8 bits per sample"), std::string::npos) << error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(src.data(), 4, 4, 8, 17, dst.data(), 4, &error));
  EXPECT_NE(error.find("17 bits per sample"), std::string::npos) << error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(src.data(), 4, 4, 7, 12, dst.data(), 4, &error));
  EXPECT_NE(error.find("source rows 7 bytes apart"), std::string::npos) << error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(src.data(), 4, 4, 8, 12, dst.data(), 3, &error));
  EXPECT_NE(error.find("destination rows 3 bytes apart"), std::string::npos) << error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(src.data(), 0, 4, 8, 12, dst.data(), 4, &error));
  EXPECT_NE(error.find("empty image"), std::string::npos) << error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(nullptr, 4, 4, 8, 12, dst.data(), 4, &error));
  EXPECT_NE(error.find("no pixels"), std::string::npos) << error;
  EXPECT_FALSE(cameras::narrowSamplesTo8Bits(src.data(), 4, 4, 8, 8, dst.data(), 4, nullptr));  // no error string: no crash
  EXPECT_TRUE(cameras::narrowSamplesTo8Bits(src.data(), 4, 4, 8, 12, dst.data(), 4, nullptr));
}

}  // namespace
}  // namespace telesphere::robot
