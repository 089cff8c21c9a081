// SPDX-License-Identifier: MIT
/// @brief JpegDecoder: native YUV planes with the right sizes and values; corrupt, truncated,
///        oversized and mismatching JPEGs refused before or instead of decoding garbage.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include "xr/video/jpeg_decoder.h"

namespace telesphere::xr {
namespace {

/// A w×h JPEG of one flat colour.
std::vector<std::uint8_t> flatJpeg(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b, int subsamp) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = r;
    rgb[i + 1] = g;
    rgb[i + 2] = b;
  }
  tjhandle c = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long size = 0;
  EXPECT_EQ(tjCompress2(c, rgb.data(), w, 0, h, TJPF_RGB, &out, &size, subsamp, 95, 0), 0);
  std::vector<std::uint8_t> jpeg(out, out + size);
  tjFree(out);
  tjDestroy(c);
  return jpeg;
}

TEST(JpegDecoder, DecodesToNativeYuvPlanes) {
  video::JpegDecoder decoder;
  render::YuvPlanes planes;
  std::string error;
  // Pure red: Y = 76, U = 85, V = 255 (JFIF full-range BT.601).
  const auto jpeg = flatJpeg(66, 50, 255, 0, 0, TJSAMP_420);
  ASSERT_EQ(decoder.decode(jpeg, 66, 50, 8192, planes, &error), video::JpegDecodeError::kNone) << error;
  EXPECT_EQ(planes.subsampling, link::ChromaSubsampling::k420);
  EXPECT_EQ(planes.y.size(), 66u * 50u);
  EXPECT_EQ(planes.chroma_width, 33);
  EXPECT_EQ(planes.chroma_height, 25);
  EXPECT_NEAR(planes.y[0], 76, 2);
  EXPECT_NEAR(planes.u[0], 85, 2);
  EXPECT_NEAR(planes.v[0], 255, 2);
  const auto gray = flatJpeg(16, 16, 200, 200, 200, TJSAMP_GRAY);
  ASSERT_EQ(decoder.decode(gray, 0, 0, 8192, planes, &error), video::JpegDecodeError::kNone) << error;
  EXPECT_EQ(planes.subsampling, link::ChromaSubsampling::kGray);
  EXPECT_TRUE(planes.u.empty());
  EXPECT_NEAR(planes.y[0], 200, 2);
}

TEST(JpegDecoder, RefusesBadJpegs) {
  video::JpegDecoder decoder;
  render::YuvPlanes planes;
  std::string error;
  const auto jpeg = flatJpeg(64, 48, 10, 200, 30, TJSAMP_420);
  // Truncated: the operator keeps the previous frame rather than half a grey one.
  const std::vector<std::uint8_t> truncated(jpeg.begin(), jpeg.begin() + jpeg.size() / 2);
  EXPECT_EQ(decoder.decode(truncated, 64, 48, 8192, planes, &error), video::JpegDecodeError::kCorrupt);
  EXPECT_EQ(decoder.decode({}, 64, 48, 8192, planes, &error), video::JpegDecodeError::kCorrupt);
  const std::vector<std::uint8_t> garbage(1000, 0x5a);
  EXPECT_NE(decoder.decode(garbage, 64, 48, 8192, planes, &error), video::JpegDecodeError::kNone);
  EXPECT_EQ(decoder.decode(jpeg, 640, 480, 8192, planes, &error), video::JpegDecodeError::kSizeMismatch);
  EXPECT_EQ(error, "JPEG is 64x48, the message said 640x480");
  // A header claiming 60000×60000 is refused before any plane is allocated.
  auto huge = jpeg;
  for (std::size_t i = 0; i + 8 < huge.size(); ++i) {
    if (huge[i] == 0xFF && huge[i + 1] == 0xC0) {  // SOF0: length(2) precision(1) height(2) width(2)
      huge[i + 5] = 0xEA;
      huge[i + 6] = 0x60;
      huge[i + 7] = 0xEA;
      huge[i + 8] = 0x60;
      break;
    }
  }
  planes = render::YuvPlanes{};
  EXPECT_EQ(decoder.decode(huge, 0, 0, 8192, planes, &error), video::JpegDecodeError::kTooLarge);
  EXPECT_EQ(error, "JPEG of 60000x60000 exceeds the limit of 8192 px per side");
  EXPECT_TRUE(planes.y.empty());
  // And the decoder still works afterwards.
  EXPECT_EQ(decoder.decode(jpeg, 64, 48, 8192, planes, &error), video::JpegDecodeError::kNone) << error;
}

}  // namespace
}  // namespace telesphere::xr
