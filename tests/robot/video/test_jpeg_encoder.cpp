// SPDX-License-Identifier: MIT
/// @brief JpegEncoder: real libjpeg-turbo round trips (fidelity rises with quality, size with it),
///        every subsampling, and refusal of bad sizes and settings.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>

#include "robot/video/jpeg_encoder.h"

namespace telesphere::robot {
namespace {

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

TEST(JpegEncoder, RefusesBadInput) {
  video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg, rgb(300);
  std::string error;
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 0, 10, 30, {}, jpeg, &error));
  EXPECT_NE(error.find("bad image size 0x10"), std::string::npos);
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 10, 10, 20, {}, jpeg, &error));  // stride too short
  EXPECT_FALSE(encoder.encodeRgb(rgb.data(), 10, 10, 30, {101, video::ChromaSubsampling::k420}, jpeg, &error));
  EXPECT_EQ(error, "JPEG quality 101 is outside 1..100");
}

}  // namespace
}  // namespace telesphere::robot
