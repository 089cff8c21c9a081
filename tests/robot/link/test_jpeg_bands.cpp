// SPDX-License-Identifier: MIT
/// @brief findJpegBands and appendFillerBand on real JPEGs from the robot's encoder: one band per
///        restart interval whose sizes add up, a filler band that keeps the JPEG valid and turns
///        exactly that band's rows mid grey (every other pixel bit-identical), at 4:2:0, 4:4:4
///        and grey, odd sizes and the extremes; and refusal of what the media path cannot use.
#include <gtest/gtest.h>

#include <numeric>

#include "robot/link/media/jpeg_bands.h"
#include "tests/robot/link/media_test_jpegs.h"

namespace telesphere::link::media {
namespace {

struct Shape {
  int width, height;
  ChromaSubsampling subsampling;
  int restart_mcu_rows;
  std::size_t bands;  ///< expected
};

const Shape kShapes[] = {
    {64, 50, ChromaSubsampling::k420, 1, 4},   // 16-row MCUs, the last one partial
    {64, 50, ChromaSubsampling::k420, 3, 2},
    {72, 40, ChromaSubsampling::k444, 1, 5},   // 8-row MCUs
    {40, 33, ChromaSubsampling::kGray, 2, 3},  // grey: one block per MCU, 5 rows of 8
    {64, 48, ChromaSubsampling::k422, 0, 1},   // no restarts: the whole image is one band
    {8, 8, ChromaSubsampling::k420, 1, 1},     // smaller than one MCU
};

std::vector<std::uint8_t> withFillerFor(const std::vector<std::uint8_t>& jpeg, const JpegBands& bands, std::size_t band) {
  std::vector<std::uint8_t> out(jpeg.begin(), jpeg.begin() + bands.header_bytes);
  std::string error;
  for (std::size_t b = 0; b < bands.bands(); ++b) {
    if (b == band) {
      EXPECT_TRUE(appendFillerBand({jpeg.data(), bands.header_bytes}, bands, b, out, &error)) << error;
    } else {
      const auto* at = jpeg.data() + bands.bandOffset(b);
      out.insert(out.end(), at, at + bands.band_bytes[b]);
    }
  }
  out.insert(out.end(), jpeg.end() - bands.trailer_bytes, jpeg.end());
  return out;
}

TEST(JpegBands, OneBandPerRestartIntervalAndTheSizesAddUp) {
  for (const Shape& s : kShapes) {
    SCOPED_TRACE(std::to_string(s.width) + "x" + std::to_string(s.height) + " restart " + std::to_string(s.restart_mcu_rows));
    const auto jpeg = test::encodeJpeg(s.width, s.height, s.subsampling, s.restart_mcu_rows);
    std::string error;
    const auto bands = findJpegBands(jpeg, &error);
    ASSERT_TRUE(bands) << error;
    EXPECT_EQ(bands->bands(), s.bands);
    EXPECT_EQ(bands->bandCount(), s.bands);
    EXPECT_EQ(bands->width, s.width);
    EXPECT_EQ(bands->height, s.height);
    EXPECT_EQ(bands->trailer_bytes, 2u);
    const std::uint64_t sum = std::accumulate(bands->band_bytes.begin(), bands->band_bytes.end(), std::uint64_t{0});
    EXPECT_EQ(bands->header_bytes + sum + bands->trailer_bytes, jpeg.size());
    // Every band but the last ends in its RSTn; the bands' rows tile the image.
    int next_row = 0;
    for (std::size_t b = 0; b < bands->bands(); ++b) {
      const std::size_t end = bands->bandOffset(b) + bands->band_bytes[b];
      if (b + 1 < bands->bands()) {
        EXPECT_EQ(jpeg[end - 2], 0xFF);
        EXPECT_EQ(jpeg[end - 1], 0xD0 + b % 8);
      }
      const auto [first, last] = bands->bandRows(b);
      EXPECT_EQ(first, next_row);
      EXPECT_GT(last, first);
      next_row = last;
    }
    EXPECT_EQ(next_row, s.height);
  }
}

TEST(JpegBands, AFillerBandKeepsTheJpegValidAndGreysExactlyItsRows) {
  for (const Shape& s : kShapes) {
    const auto jpeg = test::encodeJpeg(s.width, s.height, s.subsampling, s.restart_mcu_rows);
    std::string error;
    const auto bands = findJpegBands(jpeg, &error);
    ASSERT_TRUE(bands) << error;
    const test::Planes original = test::decodePlanes(jpeg);
    ASSERT_TRUE(original.ok);
    for (std::size_t band = 0; band < bands->bands(); ++band) {
      SCOPED_TRACE(std::to_string(s.width) + "x" + std::to_string(s.height) + " band " + std::to_string(band));
      const auto patched = withFillerFor(jpeg, *bands, band);
      const test::Planes p = test::decodePlanes(patched);
      ASSERT_TRUE(p.ok) << "the filler made the JPEG invalid";
      const auto [first, last] = bands->bandRows(band);
      for (int y = 0; y < s.height; ++y) {
        const bool lost = y >= first && y < last;
        for (int x = 0; x < s.width; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * s.width + x;
          if (lost) {
            ASSERT_EQ(p.y[i], 128) << "y " << y << " x " << x;
          } else {
            ASSERT_EQ(p.y[i], original.y[i]) << "y " << y << " x " << x;
          }
        }
      }
      // Chroma rows scale with the planes' heights.
      if (!p.u.empty()) {
        const int c_first = first * p.chroma_height / s.height, c_last = (last * p.chroma_height + s.height - 1) / s.height;
        for (int y = 0; y < p.chroma_height; ++y)
          for (int x = 0; x < p.chroma_width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * p.chroma_width + x;
            if (y >= c_first && y < c_last) {
              ASSERT_EQ(p.u[i], 128);
              ASSERT_EQ(p.v[i], 128);
            } else {
              ASSERT_EQ(p.u[i], original.u[i]);
              ASSERT_EQ(p.v[i], original.v[i]);
            }
          }
      }
    }
  }
}

TEST(JpegBands, ThousandsOfBandsAtFullSize) {
  // 4K at one restart per MCU row: 135 bands; a restart every 4 MCUs: 8160 / 4 bands, the RSTn
  // numbers wrapping modulo 8 over a thousand times.
  auto jpeg = test::encodeJpeg(3840, 2160, ChromaSubsampling::k420, 1, 90);
  std::string error;
  auto bands = findJpegBands(jpeg, &error);
  ASSERT_TRUE(bands) << error;
  EXPECT_EQ(bands->bands(), 135u);
  EXPECT_EQ(bands->bandRows(134), (std::pair<int, int>{2144, 2160}));
  const auto patched = withFillerFor(jpeg, *bands, 67);
  EXPECT_TRUE(test::decodePlanes(patched).ok);
}

TEST(JpegBands, RefusesWhatTheMediaPathCannotSlice) {
  const auto good = test::encodeJpeg(64, 48, ChromaSubsampling::k420, 1);
  std::string error;
  const auto bands = findJpegBands(good, &error);
  ASSERT_TRUE(bands) << error;
  const auto refuses = [&](std::vector<std::uint8_t> jpeg, const std::string& why) {
    std::string e;
    EXPECT_FALSE(findJpegBands(jpeg, &e)) << why;
    EXPECT_NE(e.find(why), std::string::npos) << "said: " << e;
  };
  refuses({}, "not a JPEG");
  refuses({0xFF, 0xD8, 0xFF, 0xD9, 0, 0}, "marker 0xFFD9 before the SOS segment");
  refuses({0xFF, 0xD8, 0xFF, 0xE0}, "ends before its SOS");
  refuses(std::vector<std::uint8_t>(good.begin(), good.begin() + bands->header_bytes - 3), "runs past the JPEG's end");
  refuses(std::vector<std::uint8_t>(good.begin(), good.end() - 2), "no EOI");
  {
    // RST1 where RST0 belongs.
    auto bad = good;
    bad[bands->bandOffset(1) - 1] = 0xD1;
    refuses(bad, "RST1 where RST0 belongs");
  }
  {
    // The last band and its RST1 cut off: one band missing.
    std::vector<std::uint8_t> bad(good.begin(), good.begin() + bands->bandOffset(2) - 2);
    bad.push_back(0xFF);
    bad.push_back(0xD9);
    refuses(bad, "2 bands where the restart interval gives 3");
  }
  {
    // An empty last band (EOI straight after RST1).
    std::vector<std::uint8_t> bad(good.begin(), good.begin() + bands->bandOffset(2));
    bad.push_back(0xFF);
    bad.push_back(0xD9);
    refuses(bad, "an empty band");
  }
  {
    // A progressive JPEG from libjpeg-turbo.
    tjhandle c = tjInitCompress();
    const auto rgb = test::texturedRgb(32, 32);
    unsigned char* out = nullptr;
    unsigned long size = 0;
    ASSERT_EQ(tjCompress2(c, rgb.data(), 32, 0, 32, TJPF_RGB, &out, &size, TJSAMP_420, 80, TJFLAG_PROGRESSIVE), 0);
    refuses(std::vector<std::uint8_t>(out, out + size), "not a baseline Huffman JPEG");
    tjFree(out);
    tjDestroy(c);
  }
  // A filler for a band the header does not have, or for another image's layout.
  std::vector<std::uint8_t> out;
  EXPECT_FALSE(appendFillerBand({good.data(), bands->header_bytes}, *bands, 3, out, &error));
  JpegBands other = *bands;
  other.mcus_total += 1;
  EXPECT_FALSE(appendFillerBand({good.data(), bands->header_bytes}, other, 0, out, &error));
  EXPECT_EQ(error, "the band layout does not belong to this header");
}

}  // namespace
}  // namespace telesphere::link::media
