// SPDX-License-Identifier: MIT
/// @brief JPEG encoding of camera images with libjpeg-turbo (its libjpeg API, DESIGN.md §4).
///        Quality and chroma subsampling are the speed/size/fidelity knobs; restart markers
///        after every few MCU rows let the Internet link slice a frame into bands that decode
///        on their own (DESIGN.md §9). One encoder per thread (a compressor is not thread-safe),
///        so both cameras encode in parallel.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot/cameras/yuv420_image.h"
#include "robot/link/chroma_subsampling.h"

namespace telesphere::robot::video {

using ChromaSubsampling = link::ChromaSubsampling;  ///< the video path's one chroma enum

struct JpegSettings {
  int quality = 90;  ///< 1..100
  ChromaSubsampling subsampling = ChromaSubsampling::k420;
  /// A restart marker (RSTn) after every this many MCU rows (an MCU row is 16 image rows at
  /// 4:2:0, 8 otherwise); 0: none. Restarts change no pixel: each band's entropy-coded data
  /// then starts afresh, so a band lost on the network costs that band, not the rest of the
  /// image. Costs about 2.5 bytes per marker. 0..65535.
  int restart_mcu_rows = 0;
};

class JpegEncoder {
 public:
  JpegEncoder();
  ~JpegEncoder();
  JpegEncoder(const JpegEncoder&) = delete;
  JpegEncoder& operator=(const JpegEncoder&) = delete;

  /// Encodes an 8-bit RGB image (rows `stride` bytes apart) into out_jpeg (reused, resized).
  /// Returns false with the reason in *error for bad sizes, settings or a libjpeg-turbo failure.
  bool encodeRgb(const std::uint8_t* rgb, int width, int height, int stride,
                 const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                 std::string* error);

  /// Encodes YUV 4:2:0 planes (JFIF YCbCr, as cameras::DebayerToYuv420 makes them) as they are:
  /// no colour conversion, no downsampling (libjpeg's raw-data path, restart markers as
  /// encodeRgb). `settings.subsampling` must be 4:2:0, or gray (the Y plane alone); 4:2:2 and
  /// 4:4:4 cannot come from 4:2:0 planes and are refused. Sizes that are not multiples of 16 are
  /// padded by repeating the last row and column, as libjpeg pads an RGB image; the padding rows
  /// are kept between calls (nothing allocated per frame once the size is known).
  bool encodeYuv420(const cameras::Yuv420Image& image, const JpegSettings& settings,
                    std::vector<std::uint8_t>& out_jpeg, std::string* error);

  /// Encodes an 8-bit single-channel image (a Mono8 camera) as a greyscale JPEG; `settings`'
  /// subsampling is ignored.
  bool encodeGray(const std::uint8_t* gray, int width, int height, int stride,
                  const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                  std::string* error);

 private:
  bool encode(const std::uint8_t* pixels, int width, int height, int stride, int channels,
              const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
              std::string* error);
  /// The checks every encode makes before libjpeg sees the image.
  static bool checkInput(int width, int height, const JpegSettings& settings, std::string* error);

  struct Compressor;
  std::unique_ptr<Compressor> compressor_;
};

}  // namespace telesphere::robot::video
