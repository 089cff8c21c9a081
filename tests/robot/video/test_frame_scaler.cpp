// SPDX-License-Identifier: MIT
/// @brief scaleFrame: sizes even and never below 16 px, the full-size frame passed through
///        untouched, area resampling that keeps a flat image flat and a ramp's mean, RGB and mono,
///        stamps kept; a Bayer mosaic scaled as the RGB image it shows.
#include <gtest/gtest.h>

#include <numeric>

#include "robot/video/frame_scaler.h"

namespace telesphere::robot {
namespace {

cameras::CameraFrame rampFrame(int w, int h, cameras::PixelFormat format) {
  const int channels = format == cameras::PixelFormat::kMono8 ? 1 : 3;
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(w) * h * channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c)
        (*pixels)[(static_cast<std::size_t>(y) * w + x) * channels + c] = static_cast<std::uint8_t>((x * 255) / (w - 1));
  cameras::CameraFrame f;
  f.format = format;
  f.width = w;
  f.height = h;
  f.stride_bytes = w * channels;
  f.pixels = pixels;
  f.capture_ns = 123;
  f.sequence = 7;
  f.exposure_us = 8000;
  return f;
}

double mean(const cameras::CameraFrame& f) {
  return std::accumulate(f.pixels->begin(), f.pixels->end(), 0.0) / static_cast<double>(f.pixels->size());
}

TEST(FrameScaler, SizesAreEvenAndNeverBelowSixteen) {
  EXPECT_EQ(video::scaledSize(3840, 2160, 1.0), (std::pair<int, int>{3840, 2160}));
  EXPECT_EQ(video::scaledSize(3840, 2160, 0.75), (std::pair<int, int>{2880, 1620}));
  EXPECT_EQ(video::scaledSize(3840, 2160, 0.35), (std::pair<int, int>{1344, 756}));
  EXPECT_EQ(video::scaledSize(641, 361, 0.5), (std::pair<int, int>{320, 180}));
  EXPECT_EQ(video::scaledSize(64, 48, 0.01), (std::pair<int, int>{16, 16}));
  EXPECT_EQ(video::scaledSize(10, 10, 0.01), (std::pair<int, int>{10, 10})) << "never larger than the frame";
}

TEST(FrameScaler, AreaResamplingKeepsTheImagesMeanAndTheStamps) {
  for (auto format : {cameras::PixelFormat::kRgb8, cameras::PixelFormat::kMono8}) {
    const auto full = rampFrame(640, 360, format);
    const auto same = video::scaleFrame(full, 1.0);
    EXPECT_EQ(same.pixels, full.pixels) << "scale 1 copies nothing";
    const auto half = video::scaleFrame(full, 0.5);
    EXPECT_EQ(half.width, 320);
    EXPECT_EQ(half.height, 180);
    EXPECT_EQ(half.stride_bytes, 320 * (format == cameras::PixelFormat::kMono8 ? 1 : 3));
    EXPECT_EQ(half.capture_ns, 123);
    EXPECT_EQ(half.sequence, 7u);
    EXPECT_EQ(half.exposure_us, 8000u);
    EXPECT_NEAR(mean(half), mean(full), 0.5);
    const auto odd = video::scaleFrame(full, 0.35);
    EXPECT_NEAR(mean(odd), mean(full), 1.0);
    // The ramp stays a ramp: left edge dark, right edge bright.
    EXPECT_LT((*half.pixels)[0], 5);
    EXPECT_GT((*half.pixels)[static_cast<std::size_t>(half.stride_bytes) - 1], 250);
  }
}

TEST(FrameScaler, ABayerMosaicIsScaledAsTheRgbImageItShows) {
  // A camera's raw mosaic (#34) of a grey ramp: the scaled frame is RGB, the ramp and its mean kept,
  // the stamps too; at scale 1 the mosaic passes untouched.
  for (auto layout : {cameras::PixelFormat::kBayerRG8, cameras::PixelFormat::kBayerBG8}) {
    cameras::CameraFrame mosaic = rampFrame(640, 360, cameras::PixelFormat::kMono8);
    mosaic.format = layout;  // a grey ramp: every colour's samples equal
    EXPECT_EQ(video::scaleFrame(mosaic, 1.0).pixels, mosaic.pixels);
    const auto half = video::scaleFrame(mosaic, 0.5);
    EXPECT_EQ(half.format, cameras::PixelFormat::kRgb8);
    EXPECT_EQ(half.width, 320);
    EXPECT_EQ(half.height, 180);
    EXPECT_EQ(half.stride_bytes, 320 * 3);
    EXPECT_EQ(half.sequence, 7u);
    EXPECT_NEAR(mean(half), mean(mosaic), 0.5);
    EXPECT_LT((*half.pixels)[0], 5);
    EXPECT_GT((*half.pixels)[static_cast<std::size_t>(half.stride_bytes) - 1], 250);
  }
}

}  // namespace
}  // namespace telesphere::robot
