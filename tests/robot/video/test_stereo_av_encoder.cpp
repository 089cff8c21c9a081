// SPDX-License-Identifier: MIT
/// @brief The robot's H.264/HEVC stereo encoder (#34) and the planes it encodes from: any camera
///        image (RGB against a double-precision BT.601 reference, grey, each Bayer layout against
///        DebayerToYuv420, padded rows) becomes JFIF 4:2:0 planes, a frame that does not hold its
///        pixels is refused; both cameras start with a key-frame pair, force key frames together
///        every interval and on request (several requests before one pair count once), open again
///        with a key frame when the size changes, change the rate in place (x264) or open again
///        when HEVC's moves by more than 10 %; mismatched sizes and MJPEG are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "robot/cameras/debayer_yuv420.h"
#include "robot/clock/clock.h"
#include "robot/video/frame_to_yuv420.h"
#include "robot/video/stereo_av_encoder.h"

namespace telesphere::robot::video {
namespace {

using cameras::CameraFrame;
using cameras::PixelFormat;

/// A seeded random image of `format` with `pad` bytes after each row.
CameraFrame randomFrame(PixelFormat format, int width, int height, int pad, unsigned seed) {
  CameraFrame f;
  f.format = format;
  f.width = width;
  f.height = height;
  f.stride_bytes = width * cameras::bytesPerPixel(format) + pad;
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(f.stride_bytes) * height);
  std::mt19937 rng(seed);
  for (auto& p : *pixels) p = static_cast<std::uint8_t>(rng() & 0xff);
  f.pixels = std::move(pixels);
  return f;
}

/// A smooth RGB scene moving `t` pixels: what an encoder at a modest rate reproduces well.
CameraFrame movingScene(int width, int height, int t) {
  CameraFrame f;
  f.format = PixelFormat::kRgb8;
  f.width = width;
  f.height = height;
  f.stride_bytes = width * 3;
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = pixels->data() + (static_cast<std::size_t>(y) * width + x) * 3;
      p[0] = static_cast<std::uint8_t>(128 + 90 * std::sin(0.07 * (x + 3 * t)));
      p[1] = static_cast<std::uint8_t>(128 + 90 * std::cos(0.05 * (y + t)));
      p[2] = static_cast<std::uint8_t>((x + y + 4 * t) & 0xff);
    }
  f.pixels = std::move(pixels);
  return f;
}

TEST(FrameToYuv420, RgbIsJfifBt601FullRangeWithinOne) {
  const CameraFrame f = randomFrame(PixelFormat::kRgb8, 37, 23, 5, 1);  // odd width and height, padded rows
  FrameToYuv420 convert;
  cameras::Yuv420Image planes;
  std::string error;
  ASSERT_TRUE(convert.convert(f, planes, &error)) << error;
  ASSERT_EQ(planes.width, 37);
  ASSERT_EQ(planes.chromaWidth(), 19);
  const auto rgb = [&](int x, int y, int c) {
    return double((*f.pixels)[static_cast<std::size_t>(y) * f.stride_bytes + static_cast<std::size_t>(x) * 3 + c]);
  };
  int worst_y = 0, worst_c = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const double luma = 0.299 * rgb(x, y, 0) + 0.587 * rgb(x, y, 1) + 0.114 * rgb(x, y, 2);
      worst_y = std::max(worst_y, std::abs(int(planes.y[static_cast<std::size_t>(y) * 37 + x]) - int(std::lround(luma))));
    }
  for (int cy = 0; cy < planes.chromaHeight(); ++cy)
    for (int cx = 0; cx < planes.chromaWidth(); ++cx) {
      double cb = 0, cr = 0;
      int n = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int x = std::min(2 * cx + dx, f.width - 1), y = std::min(2 * cy + dy, f.height - 1);
          cb += 128 - 0.168736 * rgb(x, y, 0) - 0.331264 * rgb(x, y, 1) + 0.5 * rgb(x, y, 2);
          cr += 128 + 0.5 * rgb(x, y, 0) - 0.418688 * rgb(x, y, 1) - 0.081312 * rgb(x, y, 2);
          ++n;
        }
      const std::size_t i = static_cast<std::size_t>(cy) * planes.chromaWidth() + cx;
      worst_c = std::max({worst_c, std::abs(int(planes.u[i]) - int(std::lround(cb / n))),
                          std::abs(int(planes.v[i]) - int(std::lround(cr / n)))});
    }
  EXPECT_LE(worst_y, 1);
  EXPECT_LE(worst_c, 1);  // the mean of four converted pixels, each rounded
}

TEST(FrameToYuv420, GreyKeepsItsValuesWithNeutralChroma) {
  const CameraFrame f = randomFrame(PixelFormat::kMono8, 20, 11, 3, 2);
  FrameToYuv420 convert;
  cameras::Yuv420Image planes;
  std::string error;
  ASSERT_TRUE(convert.convert(f, planes, &error)) << error;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 20; ++x)
      ASSERT_EQ(planes.y[static_cast<std::size_t>(y) * 20 + x], (*f.pixels)[static_cast<std::size_t>(y) * 23 + x]);
  for (std::size_t i = 0; i < planes.u.size(); ++i) {
    EXPECT_EQ(planes.u[i], 128);
    EXPECT_EQ(planes.v[i], 128);
  }
}

TEST(FrameToYuv420, EveryBayerLayoutAsDebayerToYuv420Makes) {
  for (const PixelFormat layout : {PixelFormat::kBayerRG8, PixelFormat::kBayerGR8, PixelFormat::kBayerGB8,
                                   PixelFormat::kBayerBG8}) {
    SCOPED_TRACE(cameras::pixelFormatName(layout));
    const CameraFrame f = randomFrame(layout, 34, 18, 6, 3);
    FrameToYuv420 convert;
    cameras::Yuv420Image planes, reference;
    cameras::DebayerToYuv420 debayer;
    std::string error;
    ASSERT_TRUE(convert.convert(f, planes, &error)) << error;
    ASSERT_TRUE(debayer.convert(f.pixels->data(), 34, 18, f.stride_bytes, layout, reference, &error)) << error;
    EXPECT_EQ(planes.y, reference.y);
    EXPECT_EQ(planes.u, reference.u);
    EXPECT_EQ(planes.v, reference.v);
  }
}

TEST(FrameToYuv420, AFrameShortOfItsPixelsIsRefusedWithTheSizes) {
  CameraFrame f = randomFrame(PixelFormat::kRgb8, 16, 16, 0, 4);
  f.height = 17;  // one row more than the buffer holds
  FrameToYuv420 convert;
  cameras::Yuv420Image planes;
  std::string error;
  EXPECT_FALSE(convert.convert(f, planes, &error));
  EXPECT_NE(error.find("16x17"), std::string::npos) << error;
  f.height = 1;
  EXPECT_FALSE(convert.convert(f, planes, &error));
  f.height = 16;
  f.pixels.reset();
  EXPECT_FALSE(convert.convert(f, planes, &error));
}

class StereoAvEncoderTest : public ::testing::TestWithParam<link::VideoCodec> {};

TEST_P(StereoAvEncoderTest, KeyFramesTogetherFirstEveryIntervalAndOnRequest) {
  clock::SteadyClock clock;
  StereoAvEncoderOptions o;
  o.codec = GetParam();
  o.bit_rate_bps = 4'000'000;
  o.fps = 30;
  o.key_frame_interval = 10;
  StereoAvEncoder encoder(clock, o);
  std::string error;
  std::vector<int> keys;
  for (int t = 0; t < 25; ++t) {
    if (t == 14) {
      encoder.requestKeyFrame();
      encoder.requestKeyFrame();  // two before one pair: one key-frame pair
    }
    EncodedAccessUnitPair pair;
    ASSERT_TRUE(encoder.encode(movingScene(96, 64, t), movingScene(96, 64, t + 1), pair, &error)) << error;
    ASSERT_TRUE(pair.left.bytes && pair.right.bytes);
    EXPECT_GT(pair.left.bytes->size(), 0u);
    EXPECT_GT(pair.left.encoded_ns, 0);
    if (pair.key_frame) keys.push_back(t);
  }
  // First, on request at 14, then the interval counts from there: 24.
  EXPECT_EQ(keys, (std::vector<int>{0, 10, 14, 24}));
  const StereoAvEncoderStats s = encoder.stats();
  EXPECT_EQ(s.pairs, 25u);
  EXPECT_EQ(s.key_frames, 4u);
  EXPECT_EQ(s.key_frames_requested, 1u);
  EXPECT_EQ(s.backend, GetParam() == link::VideoCodec::kH264 ? "libx264" : "libx265");
  EXPECT_EQ(s.reopened, 0u);
}

TEST_P(StereoAvEncoderTest, ANewSizeOpensAgainWithAKeyFrame) {
  clock::SteadyClock clock;
  StereoAvEncoderOptions o;
  o.codec = GetParam();
  o.key_frame_interval = 100;
  StereoAvEncoder encoder(clock, o);
  std::string error;
  EncodedAccessUnitPair pair;
  ASSERT_TRUE(encoder.encode(movingScene(96, 64, 0), movingScene(96, 64, 0), pair, &error)) << error;
  ASSERT_TRUE(encoder.encode(movingScene(96, 64, 1), movingScene(96, 64, 1), pair, &error)) << error;
  EXPECT_FALSE(pair.key_frame);
  ASSERT_TRUE(encoder.encode(movingScene(64, 48, 2), movingScene(64, 48, 2), pair, &error)) << error;
  EXPECT_TRUE(pair.key_frame);
  EXPECT_EQ(encoder.stats().reopened, 1u);
}

TEST_P(StereoAvEncoderTest, ARateChangeTakesEffectInPlaceOrByOpeningAgain) {
  clock::SteadyClock clock;
  StereoAvEncoderOptions o;
  o.codec = GetParam();
  o.bit_rate_bps = 8'000'000;
  o.key_frame_interval = 1000;
  StereoAvEncoder encoder(clock, o);
  std::string error;
  EncodedAccessUnitPair pair;
  for (int t = 0; t < 3; ++t) ASSERT_TRUE(encoder.encode(movingScene(96, 64, t), movingScene(96, 64, t), pair, &error)) << error;
  encoder.setBitRate(8'400'000);  // 5 %: nothing to open again for
  ASSERT_TRUE(encoder.encode(movingScene(96, 64, 3), movingScene(96, 64, 3), pair, &error)) << error;
  EXPECT_EQ(encoder.stats().reopened, 0u);
  encoder.setBitRate(2'000'000);
  ASSERT_TRUE(encoder.encode(movingScene(96, 64, 4), movingScene(96, 64, 4), pair, &error)) << error;
  if (GetParam() == link::VideoCodec::kHevc) {  // libx265's wrapper cannot change its rate
    EXPECT_EQ(encoder.stats().reopened, 1u);
    EXPECT_TRUE(pair.key_frame);
  } else {
    EXPECT_EQ(encoder.stats().reopened, 0u);
    EXPECT_FALSE(pair.key_frame);
  }
}

TEST_P(StereoAvEncoderTest, EveryCameraFormatGoesIn) {
  clock::SteadyClock clock;
  StereoAvEncoderOptions o;
  o.codec = GetParam();
  StereoAvEncoder encoder(clock, o);
  std::string error;
  for (const PixelFormat format : {PixelFormat::kRgb8, PixelFormat::kMono8, PixelFormat::kBayerRG8, PixelFormat::kBayerBG8}) {
    EncodedAccessUnitPair pair;
    EXPECT_TRUE(encoder.encode(randomFrame(format, 64, 32, 4, 5), randomFrame(format, 64, 32, 4, 6), pair, &error))
        << cameras::pixelFormatName(format) << ": " << error;
  }
}

TEST_P(StereoAvEncoderTest, RefusesWhatItCannotEncodeWithTheReason) {
  clock::SteadyClock clock;
  StereoAvEncoderOptions o;
  o.codec = GetParam();
  StereoAvEncoder encoder(clock, o);
  std::string error;
  EncodedAccessUnitPair pair;
  EXPECT_FALSE(encoder.encode(movingScene(96, 64, 0), movingScene(64, 64, 0), pair, &error));
  EXPECT_NE(error.find("differ in size"), std::string::npos) << error;
  EXPECT_FALSE(encoder.encode(movingScene(95, 63, 0), movingScene(95, 63, 0), pair, &error));  // odd
  EXPECT_NE(error.find("95x63"), std::string::npos) << error;
  o.codec = link::VideoCodec::kMjpeg;
  StereoAvEncoder mjpeg(clock, o);
  EXPECT_FALSE(mjpeg.encode(movingScene(96, 64, 0), movingScene(96, 64, 0), pair, &error));
  EXPECT_NE(error.find("MJPEG"), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(Codecs, StereoAvEncoderTest, ::testing::Values(link::VideoCodec::kH264, link::VideoCodec::kHevc),
                         [](const auto& info) { return std::string(link::videoCodecName(info.param)); });

}  // namespace
}  // namespace telesphere::robot::video
