// SPDX-License-Identifier: MIT
/// @brief H.264 and HEVC through libavcodec (#34), robot encoder to operator decoder, on a
///        synthetic sequence with motion: every image out at once (zero latency, no B-frames)
///        and back within a PSNR bound; a key frame on request; a lost frame makes the decoder
///        refuse everything but a key frame, and the picture after that key frame is whole
///        again; a GPU encoder asked for where there is none falls back to the CPU with the
///        reason; wrong sizes and MJPEG are refused with the reason.
#include <gtest/gtest.h>

#include <cmath>

#include "robot/video/av_video_encoder.h"
#include "xr/video/av_video_decoder.h"

namespace telesphere {
namespace {

using link::VideoCodec;

/// Image `t` of a sequence: a textured background (smooth waves and fine grain, hard enough that
/// the rate binds) drifting 2 px per image and a bright square crossing it (JFIF planes, what
/// the camera path makes). `sensor_noise`: grain new in every image, as a camera's is (nothing
/// predicts it: the rate binds), else the grain moves with the background.
robot::cameras::Yuv420Image movingImage(int width, int height, int t, bool sensor_noise = false) {
  robot::cameras::Yuv420Image image;
  image.resize(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool square = x >= 20 + 3 * t && x < 60 + 3 * t && y >= 40 && y < 80;
      const std::uint32_t grain = (static_cast<std::uint32_t>(x + 2 * t) * 2654435761u) ^ (static_cast<std::uint32_t>(y) * 40503u) ^
                                  (sensor_noise ? static_cast<std::uint32_t>(t + 1) * 2246822519u : 0u);
      image.y[static_cast<std::size_t>(y) * width + x] = static_cast<std::uint8_t>(
          square ? 235 : 100 + 50 * std::sin(0.05 * (x + 2 * t)) + 30 * std::cos(0.07 * y) + (grain >> 27));
    }
  for (int y = 0; y < image.chromaHeight(); ++y)
    for (int x = 0; x < image.chromaWidth(); ++x) {
      image.u[static_cast<std::size_t>(y) * image.chromaWidth() + x] = static_cast<std::uint8_t>(128 + 30 * std::sin(0.1 * (x + t)));
      image.v[static_cast<std::size_t>(y) * image.chromaWidth() + x] = static_cast<std::uint8_t>(128 + 30 * std::cos(0.08 * y));
    }
  return image;
}

double psnrY(const robot::cameras::Yuv420Image& a, const xr::render::YuvPlanes& b) {
  double se = 0;
  for (std::size_t i = 0; i < a.y.size(); ++i) {
    const double d = double(a.y[i]) - double(b.y[i]);
    se += d * d;
  }
  return se == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 * double(a.y.size()) / se);
}

robot::video::AvVideoEncoderOptions options(VideoCodec codec) {
  robot::video::AvVideoEncoderOptions o;
  o.codec = codec;
  o.width = 320;
  o.height = 240;
  o.fps = 30;
  o.bit_rate_bps = 3'000'000;
  o.key_frame_interval = 60;
  return o;
}

class AvVideoRoundTrip : public ::testing::TestWithParam<VideoCodec> {};

TEST_P(AvVideoRoundTrip, EveryImageComesOutAtOnceAndDecodesClose) {
  std::string error;
  auto encoder = robot::video::AvVideoEncoder::open(options(GetParam()), &error);
  ASSERT_TRUE(encoder) << error;
  auto decoder = xr::video::AvVideoDecoder::open(GetParam(), 2, &error);
  ASSERT_TRUE(decoder) << error;
  robot::video::EncodedVideoFrame packet;
  xr::render::YuvPlanes decoded;
  std::size_t key_bytes = 0, predicted_bytes = 0;
  for (int t = 0; t < 30; ++t) {
    const auto image = movingImage(320, 240, t);
    ASSERT_TRUE(encoder->encode(image, false, packet, &error)) << "image " << t << ": " << error;
    EXPECT_EQ(packet.index, t) << "the packet is the image just given (no frame of latency)";
    EXPECT_EQ(packet.key_frame, t == 0) << "image " << t;
    (packet.key_frame ? key_bytes : predicted_bytes) += packet.bytes.size();
    ASSERT_EQ(decoder->decode(packet.bytes, packet.key_frame, decoded, &error), xr::video::AvDecodeResult::kFrame)
        << "image " << t << ": " << error;
    ASSERT_EQ(decoded.width, 320);
    ASSERT_EQ(decoded.height, 240);
    EXPECT_GT(psnrY(image, decoded), 32.0) << "image " << t;
  }
  EXPECT_EQ(encoder->heldBack(), 0);
  // Prediction is the point: the 29 predicted images together cost less than 29 key frames.
  EXPECT_LT(predicted_bytes, 29 * key_bytes / 2) << encoder->backend();
}

TEST_P(AvVideoRoundTrip, ALostFrameWaitsForTheKeyFrameItAsksFor) {
  std::string error;
  auto encoder = robot::video::AvVideoEncoder::open(options(GetParam()), &error);
  ASSERT_TRUE(encoder) << error;
  auto decoder = xr::video::AvVideoDecoder::open(GetParam(), 2, &error);
  ASSERT_TRUE(decoder) << error;
  robot::video::EncodedVideoFrame packet;
  xr::render::YuvPlanes decoded;
  bool key_requested = false;
  int first_whole_after_loss = -1;
  for (int t = 0; t < 24; ++t) {
    const auto image = movingImage(320, 240, t);
    // The robot honours a request at its next image.
    ASSERT_TRUE(encoder->encode(image, key_requested, packet, &error)) << error;
    EXPECT_EQ(packet.key_frame, t == 0 || key_requested) << "image " << t;
    key_requested = false;
    if (t == 10) {  // lost on the way: the receiver sees a gap in the sequence
      decoder->markLost();
      continue;
    }
    const auto result = decoder->decode(packet.bytes, packet.key_frame, decoded, &error);
    if (t > 10 && t < 13) {
      EXPECT_EQ(result, xr::video::AvDecodeResult::kWaitingForKeyFrame) << "image " << t;
      if (t == 12) key_requested = true;  // the request reaches the robot two images late
      continue;
    }
    ASSERT_EQ(result, xr::video::AvDecodeResult::kFrame) << "image " << t << ": " << error;
    if (t > 10 && first_whole_after_loss < 0) first_whole_after_loss = t;
    EXPECT_GT(psnrY(image, decoded), 32.0) << "image " << t;
  }
  EXPECT_EQ(first_whole_after_loss, 13);
  EXPECT_FALSE(decoder->waitingForKeyFrame());
}

TEST_P(AvVideoRoundTrip, TheRateSetsTheSize) {
  // Half the bits at half the rate, roughly: the link's rate controller sets it per image.
  std::string error;
  std::size_t bytes[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    auto o = options(GetParam());
    o.bit_rate_bps = k == 0 ? 4'000'000 : 1'000'000;
    auto encoder = robot::video::AvVideoEncoder::open(o, &error);
    ASSERT_TRUE(encoder) << error;
    robot::video::EncodedVideoFrame packet;
    for (int t = 0; t < 30; ++t) {
      ASSERT_TRUE(encoder->encode(movingImage(320, 240, t, true), false, packet, &error)) << error;
      if (t >= 10) bytes[k] += packet.bytes.size();  // past the first key frame's transient
    }
  }
  EXPECT_LT(bytes[1], bytes[0] * 2 / 3) << bytes[0] << " bytes at 4 Mbit/s, " << bytes[1] << " at 1 Mbit/s";
}

TEST(AvVideoEncoder, H264TakesANewRateAtTheNextImage) {
  // The link's rate controller lowers the rate mid-stream: the images after it shrink.
  std::string error;
  auto o = options(VideoCodec::kH264);
  o.bit_rate_bps = 4'000'000;
  auto encoder = robot::video::AvVideoEncoder::open(o, &error);
  ASSERT_TRUE(encoder) << error;
  robot::video::EncodedVideoFrame packet;
  std::size_t before = 0, after = 0;
  for (int t = 0; t < 40; ++t) {
    if (t == 20) encoder->setBitRate(1'000'000);
    ASSERT_TRUE(encoder->encode(movingImage(320, 240, t, true), false, packet, &error)) << error;
    if (t >= 10 && t < 20) before += packet.bytes.size();
    if (t >= 30) after += packet.bytes.size();
  }
  EXPECT_LT(after, before * 2 / 3) << before << " bytes before, " << after << " after";
}

INSTANTIATE_TEST_SUITE_P(Codecs, AvVideoRoundTrip, ::testing::Values(VideoCodec::kH264, VideoCodec::kHevc),
                         [](const auto& info) { return std::string(link::videoCodecName(info.param)); });

TEST(AvVideoEncoder, AGpuEncoderWhereThereIsNoneFallsBackToTheCpuSayingWhy) {
  auto o = options(VideoCodec::kH264);
  o.prefer_gpu = true;
  std::string error;
  auto encoder = robot::video::AvVideoEncoder::open(o, &error);
  ASSERT_TRUE(encoder) << error;
  if (encoder->backend() == "h264_nvenc") {
    EXPECT_TRUE(encoder->gpuFallbackReason().empty());  // a machine with an NVIDIA GPU and driver
  } else {
    EXPECT_EQ(encoder->backend(), "libx264");
    EXPECT_NE(encoder->gpuFallbackReason().find("h264_nvenc"), std::string::npos) << encoder->gpuFallbackReason();
  }
}

TEST(AvVideoEncoder, RefusesWhatItCannotEncode) {
  std::string error;
  auto o = options(VideoCodec::kMjpeg);
  EXPECT_FALSE(robot::video::AvVideoEncoder::open(o, &error));
  EXPECT_NE(error.find("JpegEncoder"), std::string::npos) << error;
  o = options(VideoCodec::kH264);
  o.width = 321;
  EXPECT_FALSE(robot::video::AvVideoEncoder::open(o, &error));
  EXPECT_NE(error.find("321x240"), std::string::npos) << error;
  o = options(VideoCodec::kH264);
  o.bit_rate_bps = 0;
  EXPECT_FALSE(robot::video::AvVideoEncoder::open(o, &error));
  auto encoder = robot::video::AvVideoEncoder::open(options(VideoCodec::kH264), &error);
  ASSERT_TRUE(encoder) << error;
  robot::video::EncodedVideoFrame packet;
  EXPECT_FALSE(encoder->encode(movingImage(160, 120, 0), false, packet, &error));
  EXPECT_NE(error.find("160x120"), std::string::npos) << error;
  EXPECT_TRUE(encoder->encode(movingImage(320, 240, 0), false, packet, &error)) << error;
  EXPECT_FALSE(xr::video::AvVideoDecoder::open(VideoCodec::kMjpeg, 1, &error));
  // Garbage is an error, and the decoder then waits for a key frame.
  auto decoder = xr::video::AvVideoDecoder::open(VideoCodec::kH264, 1, &error);
  ASSERT_TRUE(decoder) << error;
  const std::vector<std::uint8_t> garbage = {0, 0, 0, 1, 0x65, 0xFF, 0x13, 0x37, 0, 0, 0, 1, 0x41, 0x9A};
  xr::render::YuvPlanes decoded;
  const auto result = decoder->decode(garbage, false, decoded, &error);
  EXPECT_NE(result, xr::video::AvDecodeResult::kFrame);
}

}  // namespace
}  // namespace telesphere
