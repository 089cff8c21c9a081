// SPDX-License-Identifier: MIT
/// @brief JpegEncoder::encodeYuv420 (#34): JPEG straight from YUV 4:2:0 planes. From the planes
///        TurboJPEG makes of an RGB image, the same bytes as encoding that RGB image (the colour
///        conversion and downsampling are the only difference, and they are done already);
///        planes of every size (odd, narrower than a block, one pixel) come back from TurboJPEG's
///        decoder to planes within a PSNR bound that rises with quality; restart markers as from
///        RGB; gray from the Y plane alone; refusals with the reason.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "robot/video/jpeg_encoder.h"
#include "tests/support/jpeg_restart_markers.h"

namespace telesphere::robot {
namespace {

using test::countRestartMarkers;

using cameras::Yuv420Image;

std::vector<std::uint8_t> smoothRgb(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> phase(0.0, 6.0);
  const double a = phase(rng), b = phase(rng), c = phase(rng);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
      p[0] = static_cast<std::uint8_t>(128 + 100 * std::sin(x * 0.09 + a));
      p[1] = static_cast<std::uint8_t>(128 + 100 * std::cos(y * 0.11 + b));
      p[2] = static_cast<std::uint8_t>(128 + 100 * std::sin((x + 2 * y) * 0.05 + c));
    }
  return rgb;
}

/// TurboJPEG's planes: its luma plane is padded to an even width and height (tjPlaneWidth), ours
/// is not; these copy between the two.
struct TurboPlanes {
  std::vector<std::uint8_t> planes[3];
  int strides[3] = {0, 0, 0};
  unsigned char* pointers[3] = {nullptr, nullptr, nullptr};
  TurboPlanes(int w, int h) {
    for (int k = 0; k < 3; ++k) {
      strides[k] = tjPlaneWidth(k, w, TJSAMP_420);
      planes[k].resize(static_cast<std::size_t>(strides[k]) * tjPlaneHeight(k, h, TJSAMP_420));
      pointers[k] = planes[k].data();
    }
  }
  Yuv420Image image(int w, int h) const {
    Yuv420Image out;
    out.resize(w, h);
    std::vector<std::uint8_t>* targets[3] = {&out.y, &out.u, &out.v};
    for (int k = 0; k < 3; ++k) {
      const int width = k == 0 ? w : out.chromaWidth(), height = k == 0 ? h : out.chromaHeight();
      for (int r = 0; r < height; ++r)
        std::copy_n(planes[k].begin() + static_cast<std::ptrdiff_t>(r) * strides[k], width,
                    targets[k]->begin() + static_cast<std::ptrdiff_t>(r) * width);
    }
    return out;
  }
};

/// TurboJPEG's own RGB → YUV 4:2:0 (the libjpeg compressor's colour conversion and downsampling).
Yuv420Image turboPlanes(const std::vector<std::uint8_t>& rgb, int w, int h) {
  TurboPlanes planes(w, h);
  tjhandle c = tjInitCompress();
  EXPECT_EQ(tjEncodeYUVPlanes(c, rgb.data(), w, 0, h, TJPF_RGB, planes.pointers, planes.strides, TJSAMP_420, 0), 0)
      << tjGetErrorStr2(c);
  tjDestroy(c);
  return planes.image(w, h);
}

/// The JPEG decoded back to planes (no upsampling, no colour conversion).
Yuv420Image decodePlanes(const std::vector<std::uint8_t>& jpeg, int w, int h) {
  TurboPlanes planes(w, h);
  tjhandle d = tjInitDecompress();
  EXPECT_EQ(tjDecompressToYUVPlanes(d, jpeg.data(), jpeg.size(), planes.pointers, w, planes.strides, h, 0), 0)
      << tjGetErrorStr2(d);
  tjDestroy(d);
  return planes.image(w, h);
}

double psnr(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  double se = 0;
  for (std::size_t i = 0; i < a.size(); ++i) se += (a[i] - b[i]) * double(a[i] - b[i]);
  return se == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 / (se / static_cast<double>(a.size())));
}


TEST(JpegEncoderYuv420, TheSameBytesAsFromTheRgbImageTheyCameFrom) {
  // Sizes on the MCU grid (16 × 16 at 4:2:0), where libjpeg pads nothing: the RGB path differs
  // from the planes path only in the conversion the planes already carry.
  video::JpegEncoder encoder;
  std::string error;
  for (auto [w, h] : {std::pair{16, 16}, {320, 240}, {64, 48}}) {
    const auto rgb = smoothRgb(w, h, static_cast<std::uint32_t>(w * h));
    const Yuv420Image planes = turboPlanes(rgb, w, h);
    for (int quality : {50, 90, 98}) {
      for (int restarts : {0, 1}) {
        std::vector<std::uint8_t> from_rgb, from_planes;
        const video::JpegSettings settings{quality, video::ChromaSubsampling::k420, restarts};
        ASSERT_TRUE(encoder.encodeRgb(rgb.data(), w, h, w * 3, settings, from_rgb, &error)) << error;
        ASSERT_TRUE(encoder.encodeYuv420(planes, settings, from_planes, &error)) << error;
        EXPECT_EQ(from_planes, from_rgb) << w << "x" << h << " q" << quality << " restarts " << restarts;
      }
    }
  }
}

TEST(JpegEncoderYuv420, EverySizeComesBackWithinItsQuality) {
  // Off the MCU grid the encoder pads the planes itself; odd sizes, narrower than one block,
  // a single pixel. The decoder's planes against the encoder's: PSNR rises with quality.
  video::JpegEncoder encoder;
  std::string error;
  std::vector<std::uint8_t> jpeg;
  for (auto [w, h] : {std::pair{1, 1}, {2, 2}, {7, 3}, {17, 9}, {33, 31}, {100, 75}, {130, 18}}) {
    const auto rgb = smoothRgb(w, h, static_cast<std::uint32_t>(7 * w + h));
    const Yuv420Image planes = turboPlanes(rgb, w, h);
    double last_y = 0;
    for (int quality : {50, 90, 100}) {
      ASSERT_TRUE(encoder.encodeYuv420(planes, {quality, video::ChromaSubsampling::k420, 1}, jpeg, &error)) << error;
      const Yuv420Image back = decodePlanes(jpeg, w, h);
      const double p_y = psnr(planes.y, back.y), p_u = psnr(planes.u, back.u), p_v = psnr(planes.v, back.v);
      EXPECT_GE(p_y, last_y) << w << "x" << h << " q" << quality;
      const double bound = quality == 100 ? 45.0 : quality == 90 ? 35.0 : 28.0;
      EXPECT_GT(p_y, bound) << w << "x" << h << " q" << quality;
      EXPECT_GT(p_u, bound) << w << "x" << h << " q" << quality;
      EXPECT_GT(p_v, bound) << w << "x" << h << " q" << quality;
      last_y = p_y;
    }
  }
}

/// `image` grown to `w` × `h` by repeating its last column and row in every plane.
Yuv420Image paddedByHand(const Yuv420Image& image, int w, int h) {
  Yuv420Image out;
  out.resize(w, h);
  const auto pad = [](const std::vector<std::uint8_t>& from, int fw, int fh, std::vector<std::uint8_t>& to, int tw,
                      int th) {
    for (int y = 0; y < th; ++y)
      for (int x = 0; x < tw; ++x)
        to[static_cast<std::size_t>(y) * tw + x] = from[static_cast<std::size_t>(std::min(y, fh - 1)) * fw + std::min(x, fw - 1)];
  };
  pad(image.y, image.width, image.height, out.y, w, h);
  pad(image.u, image.chromaWidth(), image.chromaHeight(), out.u, out.chromaWidth(), out.chromaHeight());
  pad(image.v, image.chromaWidth(), image.chromaHeight(), out.v, out.chromaWidth(), out.chromaHeight());
  return out;
}

TEST(JpegEncoderYuv420, OffTheGridThePaddingRepeatsTheEdge) {
  // The DCT sees whole blocks: an image off the 16 × 16 grid must decode to the same pixels as
  // the same image padded to the grid by hand (its last column and row repeated), cropped.
  video::JpegEncoder encoder;
  std::string error;
  for (auto [w, h] : {std::pair{1, 1}, {7, 3}, {17, 9}, {30, 30}, {33, 17}}) {
    const Yuv420Image planes = turboPlanes(smoothRgb(w, h, static_cast<std::uint32_t>(w + 3 * h)), w, h);
    const int gw = (w + 15) / 16 * 16, gh = (h + 15) / 16 * 16;
    const Yuv420Image on_grid = paddedByHand(planes, gw, gh);
    std::vector<std::uint8_t> off_jpeg, grid_jpeg;
    ASSERT_TRUE(encoder.encodeYuv420(planes, {90, video::ChromaSubsampling::k420, 0}, off_jpeg, &error)) << error;
    ASSERT_TRUE(encoder.encodeYuv420(on_grid, {90, video::ChromaSubsampling::k420, 0}, grid_jpeg, &error)) << error;
    const Yuv420Image off = decodePlanes(off_jpeg, w, h), grid = decodePlanes(grid_jpeg, gw, gh);
    const Yuv420Image cropped = paddedByHand(grid, w, h);  // the top-left w × h of every plane
    EXPECT_EQ(off.y, cropped.y) << w << "x" << h;
    EXPECT_EQ(off.u, cropped.u) << w << "x" << h;
    EXPECT_EQ(off.v, cropped.v) << w << "x" << h;
  }
}

TEST(JpegEncoderYuv420, RestartMarkersAndGrayAsFromRgb) {
  // 64 × 50: four MCU rows at 4:2:0 (the last partial), seven of 8 rows in gray.
  const int w = 64, h = 50;
  const auto rgb = smoothRgb(w, h, 3);
  const Yuv420Image planes = turboPlanes(rgb, w, h);
  video::JpegEncoder encoder;
  std::string error;
  std::vector<std::uint8_t> plain, every_row, gray;
  ASSERT_TRUE(encoder.encodeYuv420(planes, {90, video::ChromaSubsampling::k420, 0}, plain, &error)) << error;
  ASSERT_TRUE(encoder.encodeYuv420(planes, {90, video::ChromaSubsampling::k420, 1}, every_row, &error)) << error;
  EXPECT_EQ(countRestartMarkers(plain), 0);
  EXPECT_EQ(countRestartMarkers(every_row), 3);
  EXPECT_EQ(decodePlanes(every_row, w, h).y, decodePlanes(plain, w, h).y) << "restarts changed pixels";

  ASSERT_TRUE(encoder.encodeYuv420(planes, {90, video::ChromaSubsampling::kGray, 1}, gray, &error)) << error;
  EXPECT_EQ(countRestartMarkers(gray), 6);
  tjhandle d = tjInitDecompress();
  int jw = 0, jh = 0, subsampling = -1, colourspace = -1;
  ASSERT_EQ(tjDecompressHeader3(d, gray.data(), gray.size(), &jw, &jh, &subsampling, &colourspace), 0);
  EXPECT_EQ(subsampling, TJSAMP_GRAY);
  std::vector<std::uint8_t> luma(static_cast<std::size_t>(w) * h);
  ASSERT_EQ(tjDecompress2(d, gray.data(), gray.size(), luma.data(), w, 0, h, TJPF_GRAY, 0), 0);
  tjDestroy(d);
  EXPECT_GT(psnr(planes.y, luma), 35.0);
}

TEST(JpegEncoderYuv420, RefusesWhatPlanesCannotMake) {
  video::JpegEncoder encoder;
  std::string error;
  std::vector<std::uint8_t> jpeg;
  Yuv420Image planes;
  planes.resize(32, 32);
  EXPECT_FALSE(encoder.encodeYuv420(planes, {90, video::ChromaSubsampling::k444, 0}, jpeg, &error));
  EXPECT_NE(error.find("cannot make a 4:4:4 JPEG"), std::string::npos) << error;
  EXPECT_FALSE(encoder.encodeYuv420(planes, {90, video::ChromaSubsampling::k422, 0}, jpeg, &error));
  EXPECT_NE(error.find("4:2:2"), std::string::npos) << error;
  EXPECT_FALSE(encoder.encodeYuv420(planes, {0, video::ChromaSubsampling::k420, 0}, jpeg, &error));
  EXPECT_EQ(error, "JPEG quality 0 is outside 1..100");
  Yuv420Image torn = planes;
  torn.u.resize(10);  // a plane shorter than its size says
  EXPECT_FALSE(encoder.encodeYuv420(torn, {90, video::ChromaSubsampling::k420, 0}, jpeg, &error));
  EXPECT_NE(error.find("fewer than a 32x32 image needs"), std::string::npos) << error;
  Yuv420Image empty;
  EXPECT_FALSE(encoder.encodeYuv420(empty, {}, jpeg, &error));
  EXPECT_NE(error.find("bad image size 0x0"), std::string::npos) << error;
  // After refusals the same encoder still encodes.
  EXPECT_TRUE(encoder.encodeYuv420(planes, {}, jpeg, &error)) << error;
}

}  // namespace
}  // namespace telesphere::robot
