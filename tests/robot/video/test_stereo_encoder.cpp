// SPDX-License-Identifier: MIT
/// @brief StereoEncoder: both sides encode (RGB8, Mono8 and the four Bayer mosaics, #34), decode
///        back close to the input, frames it cannot encode are refused with the side named,
///        settings change live, and output buffers are reused only once nobody else holds them.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>
#include <random>

#include "robot/cameras/debayer.h"
#include "robot/cameras/debayer_yuv420.h"
#include "robot/video/stereo_encoder.h"

namespace telesphere::robot {
namespace {

cameras::CameraFrame testFrame(int width, int height, cameras::PixelFormat format, std::uint32_t seed) {
  cameras::CameraFrame f;
  f.width = width;
  f.height = height;
  f.format = format;
  f.stride_bytes = width * cameras::bytesPerPixel(format);
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(f.stride_bytes) * height);
  // Smooth content (JPEG-friendly) with a seed-dependent phase so the two sides differ.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < f.stride_bytes; ++x)
      (*pixels)[static_cast<std::size_t>(y) * f.stride_bytes + x] = static_cast<std::uint8_t>(
          127.5 + 100.0 * std::sin(0.05 * x + 0.07 * y + seed));
  f.pixels = pixels;
  return f;
}

/// Decodes to the frame's own pixel layout and returns the RMS difference.
double rmsAfterRoundTrip(const cameras::CameraFrame& f, const std::vector<std::uint8_t>& jpeg) {
  tjhandle h = tjInitDecompress();
  std::vector<std::uint8_t> out(f.pixels->size());
  const int pf = f.format == cameras::PixelFormat::kMono8 ? TJPF_GRAY : TJPF_RGB;
  EXPECT_EQ(tjDecompress2(h, jpeg.data(), jpeg.size(), out.data(), f.width, f.stride_bytes,
                          f.height, pf, 0), 0) << tjGetErrorStr2(h);
  tjDestroy(h);
  double sum = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double d = double(out[i]) - double((*f.pixels)[i]);
    sum += d * d;
  }
  return std::sqrt(sum / double(out.size()));
}

TEST(StereoEncoder, EncodesBothSidesAndTheyDecodeBack) {
  clock::SteadyClock clock;
  video::StereoEncoder encoder(clock, {90, video::ChromaSubsampling::k444});
  for (cameras::PixelFormat format : {cameras::PixelFormat::kRgb8, cameras::PixelFormat::kMono8}) {
    const cameras::CameraFrame left = testFrame(320, 240, format, 1), right = testFrame(320, 240, format, 2);
    video::EncodedPair out;
    std::string error;
    const std::int64_t before = clock.nowNs();
    ASSERT_TRUE(encoder.encode(left, right, out, &error)) << error;
    ASSERT_TRUE(out.left.jpeg && out.right.jpeg);
    EXPECT_LT(rmsAfterRoundTrip(left, *out.left.jpeg), 3.0);
    EXPECT_LT(rmsAfterRoundTrip(right, *out.right.jpeg), 3.0);
    // The sides are not swapped: left decodes far from right's content.
    EXPECT_GT(rmsAfterRoundTrip(right, *out.left.jpeg), 20.0);
    EXPECT_GE(out.left.encoded_ns, before);
    EXPECT_GE(out.right.encoded_ns, before);
    EXPECT_GT(out.left.encode_ms, 0.0);  // an encode takes time (0: not measured)
  }
}

/// What a camera with this colour filter sends of the RGB frame's scene.
cameras::CameraFrame mosaicOf(const cameras::CameraFrame& rgb, cameras::PixelFormat layout) {
  cameras::CameraFrame f = rgb;
  f.format = layout;
  f.stride_bytes = rgb.width;
  f.pixels = std::make_shared<std::vector<std::uint8_t>>(
      cameras::bayerMosaicOf(rgb.pixels->data(), rgb.width, rgb.height, rgb.stride_bytes, layout));
  return f;
}

/// The mosaic debayered to RGB (what a JPEG of it should decode close to).
cameras::CameraFrame debayered(const cameras::CameraFrame& mosaic) {
  cameras::CameraFrame f = mosaic;
  auto rgb = std::make_shared<std::vector<std::uint8_t>>();
  std::string error;
  EXPECT_TRUE(cameras::debayerBilinear(mosaic.pixels->data(), mosaic.width, mosaic.height, mosaic.stride_bytes,
                                       mosaic.format, *rgb, &error)) << error;
  f.format = cameras::PixelFormat::kRgb8;
  f.stride_bytes = mosaic.width * 3;
  f.pixels = rgb;
  return f;
}

TEST(StereoEncoder, BayerMosaicsEncodeThroughPlanesOnEachSide) {
  // Each layout, each side its own scene: the JPEG decodes close to the debayered image, the
  // sides are not swapped, and at 4:2:0 it is exactly DebayerToYuv420 + encodeYuv420's JPEG.
  clock::SteadyClock clock;
  video::StereoEncoder encoder(clock, {90, video::ChromaSubsampling::k420});
  for (cameras::PixelFormat layout : {cameras::PixelFormat::kBayerRG8, cameras::PixelFormat::kBayerGR8,
                                      cameras::PixelFormat::kBayerGB8, cameras::PixelFormat::kBayerBG8}) {
    const cameras::CameraFrame left = mosaicOf(testFrame(320, 240, cameras::PixelFormat::kRgb8, 1), layout);
    const cameras::CameraFrame right = mosaicOf(testFrame(320, 240, cameras::PixelFormat::kRgb8, 2), layout);
    video::EncodedPair out;
    std::string error;
    ASSERT_TRUE(encoder.encode(left, right, out, &error)) << cameras::pixelFormatName(layout) << ": " << error;
    EXPECT_LT(rmsAfterRoundTrip(debayered(left), *out.left.jpeg), 4.0) << cameras::pixelFormatName(layout);
    EXPECT_LT(rmsAfterRoundTrip(debayered(right), *out.right.jpeg), 4.0) << cameras::pixelFormatName(layout);
    EXPECT_GT(rmsAfterRoundTrip(debayered(right), *out.left.jpeg), 20.0) << cameras::pixelFormatName(layout);

    cameras::DebayerToYuv420 to_planes;
    cameras::Yuv420Image planes;
    video::JpegEncoder jpeg;
    std::vector<std::uint8_t> expected;
    ASSERT_TRUE(to_planes.convert(right.pixels->data(), 320, 240, 320, layout, planes, &error)) << error;
    ASSERT_TRUE(jpeg.encodeYuv420(planes, {90, video::ChromaSubsampling::k420}, expected, &error)) << error;
    EXPECT_EQ(*out.right.jpeg, expected) << cameras::pixelFormatName(layout);
  }
  // 4:4:4 and 4:2:2 cannot come from 4:2:0 planes: they go through RGB, and still decode close.
  for (video::ChromaSubsampling s : {video::ChromaSubsampling::k444, video::ChromaSubsampling::k422}) {
    const cameras::CameraFrame f = mosaicOf(testFrame(160, 120, cameras::PixelFormat::kRgb8, 3), cameras::PixelFormat::kBayerGR8);
    video::EncodedPair out;
    std::string error;
    ASSERT_TRUE(encoder.encode(f, f, {90, s}, out, &error)) << error;
    EXPECT_LT(rmsAfterRoundTrip(debayered(f), *out.left.jpeg), 3.0);
    int w = 0, h = 0, subsampling = -1, colourspace = -1;
    tjhandle d = tjInitDecompress();
    ASSERT_EQ(tjDecompressHeader3(d, out.left.jpeg->data(), out.left.jpeg->size(), &w, &h, &subsampling, &colourspace), 0);
    tjDestroy(d);
    EXPECT_EQ(subsampling, s == video::ChromaSubsampling::k444 ? TJSAMP_444 : TJSAMP_422);
  }
}

TEST(StereoEncoder, RefusesFramesItCannotEncodeNamingTheSide) {
  clock::SteadyClock clock;
  video::StereoEncoder encoder(clock, {});
  const cameras::CameraFrame good = testFrame(64, 48, cameras::PixelFormat::kRgb8, 1);
  cameras::CameraFrame sliver = testFrame(1, 48, cameras::PixelFormat::kMono8, 1);  // no 2 x 2 Bayer cell
  sliver.format = cameras::PixelFormat::kBayerRG8;
  video::EncodedPair out;
  std::string error;
  EXPECT_FALSE(encoder.encode(good, sliver, out, &error));
  EXPECT_NE(error.find("right"), std::string::npos) << error;
  EXPECT_NE(error.find("smaller than 2x2"), std::string::npos) << error;
  cameras::CameraFrame empty;
  EXPECT_FALSE(encoder.encode(empty, good, out, &error));
  EXPECT_NE(error.find("left"), std::string::npos) << error;
  // And it still works afterwards.
  EXPECT_TRUE(encoder.encode(good, good, out, &error)) << error;
}

TEST(StereoEncoder, QualityChangesLiveAndBadQualityFails) {
  clock::SteadyClock clock;
  video::StereoEncoder encoder(clock, {95, video::ChromaSubsampling::k420});
  const cameras::CameraFrame f = testFrame(256, 256, cameras::PixelFormat::kRgb8, 3);
  video::EncodedPair high, low;
  std::string error;
  ASSERT_TRUE(encoder.encode(f, f, high, &error)) << error;
  encoder.setSettings({30, video::ChromaSubsampling::k420});
  ASSERT_TRUE(encoder.encode(f, f, low, &error)) << error;
  EXPECT_LT(low.left.jpeg->size(), high.left.jpeg->size());
  encoder.setSettings({0, video::ChromaSubsampling::k420});
  EXPECT_FALSE(encoder.encode(f, f, low, &error));
  EXPECT_NE(error.find("quality"), std::string::npos) << error;
}

TEST(StereoEncoder, ReusesABufferOnlyAfterEveryoneReleasedIt) {
  clock::SteadyClock clock;
  video::StereoEncoder encoder(clock, {});
  const cameras::CameraFrame f = testFrame(128, 96, cameras::PixelFormat::kRgb8, 4);
  video::EncodedPair first, second;
  std::string error;
  ASSERT_TRUE(encoder.encode(f, f, first, &error)) << error;
  const auto held = first.left.jpeg;  // e.g. still queued in the link
  const std::vector<std::uint8_t> held_bytes = *held;
  first = {};
  ASSERT_TRUE(encoder.encode(testFrame(128, 96, cameras::PixelFormat::kRgb8, 9), f, second, &error));
  EXPECT_NE(second.left.jpeg.get(), held.get());  // not overwritten while held
  EXPECT_EQ(*held, held_bytes);
  const void* second_ptr = second.left.jpeg.get();
  second = {};
  video::EncodedPair third;
  ASSERT_TRUE(encoder.encode(f, f, third, &error));
  // A released buffer comes back (the first free one in the pool: `held`'s is still taken).
  EXPECT_EQ(third.left.jpeg.get(), second_ptr);
}

}  // namespace
}  // namespace telesphere::robot
