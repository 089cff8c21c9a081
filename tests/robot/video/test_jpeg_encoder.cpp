// SPDX-License-Identifier: MIT
/// @brief JpegEncoder: real libjpeg-turbo round trips (fidelity rises with quality, size with it),
///        every subsampling, and refusal of bad sizes and settings.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>
#include <random>

#include "robot/video/jpeg_encoder.h"
#include "tests/support/jpeg_restart_markers.h"

namespace telesphere::robot {
namespace {

using test::countRestartMarkers;

std::vector<std::uint8_t> testImage(int w, int h) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
      p[0] = static_cast<std::uint8_t>(128 + 100 * std::sin(x * 0.05));
      p[1] = static_cast<std::uint8_t>(128 + 100 * std::cos(y * 0.07));
      p[2] = static_cast<std::uint8_t>(128 + 100 * std::sin((x + 2 * y) * 0.03));
    }
  return rgb;
}

double psnr(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  double se = 0;
  for (std::size_t i = 0; i < a.size(); ++i) se += (a[i] - b[i]) * double(a[i] - b[i]);
  return 10 * std::log10(255.0 * 255.0 / (se / a.size()));
}

std::vector<std::uint8_t> decodeRgb(const std::vector<std::uint8_t>& jpeg, int w, int h) {
  tjhandle d = tjInitDecompress();
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  EXPECT_EQ(tjDecompress2(d, jpeg.data(), jpeg.size(), rgb.data(), w, 0, h, TJPF_RGB, 0), 0);
  tjDestroy(d);
  return rgb;
}

TEST(JpegEncoder, QualityTradesSizeForFidelity) {
  const int w = 320, h = 240;
  const auto rgb = testImage(w, h);
  video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg;
  std::string error;
  double last_psnr = 0;
  std::size_t last_size = 0;
  for (int quality : {50, 75, 90, 95}) {
    ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, {quality, video::ChromaSubsampling::k420}, jpeg, &error)) << error;
    const double p = psnr(rgb, decodeRgb(jpeg, w, h));
    EXPECT_GT(p, last_psnr) << "quality " << quality;
    EXPECT_GT(jpeg.size(), last_size) << "quality " << quality;
    last_psnr = p;
    last_size = jpeg.size();
  }
  EXPECT_GT(last_psnr, 35.0);
}

TEST(JpegEncoder, EverySubsamplingDecodes) {
  const int w = 64, h = 48;
  const auto rgb = testImage(w, h);
  video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg;
  std::string error;
  tjhandle d = tjInitDecompress();
  for (auto [s, tj] : {std::pair{video::ChromaSubsampling::k420, TJSAMP_420}, {video::ChromaSubsampling::k422, TJSAMP_422},
                       {video::ChromaSubsampling::k444, TJSAMP_444}, {video::ChromaSubsampling::kGray, TJSAMP_GRAY}}) {
    ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, {90, s}, jpeg, &error)) << error;
    int jw, jh, js, jc;
    ASSERT_EQ(tjDecompressHeader3(d, jpeg.data(), jpeg.size(), &jw, &jh, &js, &jc), 0);
    EXPECT_EQ(jw, w);
    EXPECT_EQ(jh, h);
    EXPECT_EQ(js, tj);
  }
  tjDestroy(d);
}


TEST(JpegEncoder, RestartMarkersAfterEveryFewMcuRowsChangeNoPixel) {
  // 64 × 50 at 4:2:0: four MCU rows of 16 (the last one partial); 4:4:4 and grey: seven of 8.
  const int w = 64, h = 50;
  const auto rgb = testImage(w, h);
  video::JpegEncoder encoder;
  std::string error;
  struct Case { video::ChromaSubsampling s; int rows_per_mcu; };
  for (auto [s, rows_per_mcu] : {Case{video::ChromaSubsampling::k420, 16}, Case{video::ChromaSubsampling::k444, 8},
                                 Case{video::ChromaSubsampling::kGray, 8}}) {
    const int mcu_rows = (h + rows_per_mcu - 1) / rows_per_mcu;
    std::vector<std::uint8_t> plain, every_row, every_two;
    ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, {90, s, 0}, plain, &error)) << error;
    ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, {90, s, 1}, every_row, &error)) << error;
    ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, {90, s, 2}, every_two, &error)) << error;
    EXPECT_EQ(countRestartMarkers(plain), 0);
    EXPECT_EQ(countRestartMarkers(every_row), mcu_rows - 1);
    EXPECT_EQ(countRestartMarkers(every_two), (mcu_rows + 1) / 2 - 1);
    EXPECT_GT(every_row.size(), plain.size());
    EXPECT_LT(every_row.size(), plain.size() + 8 * static_cast<std::size_t>(mcu_rows));
    EXPECT_EQ(decodeRgb(every_row, w, h), decodeRgb(plain, w, h)) << "restarts changed pixels";
    EXPECT_EQ(decodeRgb(every_two, w, h), decodeRgb(plain, w, h)) << "restarts changed pixels";
  }
}

TEST(JpegEncoder, OutgrowsItsFirstGuessAtTheExtremes) {
  // Noise at quality 100, 4:4:4 costs more than the half byte per sample the buffer starts at.
  const int w = 96, h = 64;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  std::mt19937 rng(7);
  for (auto& v : rgb) v = static_cast<std::uint8_t>(rng());
  video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg;
  std::string error;
  ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, {100, video::ChromaSubsampling::k444, 1}, jpeg, &error)) << error;
  EXPECT_GT(jpeg.size(), rgb.size() / 2 + 4096);
  EXPECT_GT(psnr(rgb, decodeRgb(jpeg, w, h)), 40.0);
  // Quality 1 on a 1 × 1 image, and a single-row image with restarts: still valid JPEGs.
  ASSERT_TRUE(encoder.encodeRgb(rgb.data(), 1, 1, 3, {1, video::ChromaSubsampling::k420, 1}, jpeg, &error)) << error;
  EXPECT_EQ(decodeRgb(jpeg, 1, 1).size(), 3u);
  ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, 1, w * 3, {75, video::ChromaSubsampling::k420, 1}, jpeg, &error)) << error;
  EXPECT_EQ(countRestartMarkers(jpeg), 0);
}

TEST(JpegEncoder, RefusesBadInput) {
  video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg, rgb(300);
  std::string error;
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 0, 10, 30, {}, jpeg, &error));
  EXPECT_NE(error.find("bad image size 0x10"), std::string::npos);
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 10, 10, 20, {}, jpeg, &error));  // stride too short
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 10, 10, 30, {101, video::ChromaSubsampling::k420}, jpeg, &error));
  EXPECT_EQ(error, "JPEG quality 101 is outside 1..100");
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 10, 10, 30, {90, video::ChromaSubsampling::k420, -1}, jpeg, &error));
  EXPECT_EQ(error, "JPEG restart interval of -1 MCU rows is outside 0..65535");
  // After a refusal the same encoder still encodes.
  EXPECT_TRUE(encoder.encodeRgb(rgb.data(), 10, 10, 30, {}, jpeg, &error)) << error;
}

}  // namespace
}  // namespace telesphere::robot
