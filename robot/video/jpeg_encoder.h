// SPDX-License-Identifier: MIT
/// @brief JPEG encoding of camera images with libjpeg-turbo's TurboJPEG API (DESIGN.md §4).
///        Quality and chroma subsampling are the speed/size/fidelity knobs; one encoder per
///        thread (a TurboJPEG handle is not thread-safe), so both cameras encode in parallel.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robot/link/chroma_subsampling.h"

namespace telesphere::robot::video {

using ChromaSubsampling = link::ChromaSubsampling;  ///< the video path's one chroma enum

struct JpegSettings {
  int quality = 90;  ///< 1..100
  ChromaSubsampling subsampling = ChromaSubsampling::k420;
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

  /// Encodes an 8-bit single-channel image (a Mono8 camera) as a greyscale JPEG; `settings`'
  /// subsampling is ignored.
  bool encodeGray(const std::uint8_t* gray, int width, int height, int stride,
                  const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                  std::string* error);

 private:
  bool encode(const std::uint8_t* pixels, int width, int height, int stride, int channels,
              const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
              std::string* error);

  void* handle_;
};

}  // namespace telesphere::robot::video
