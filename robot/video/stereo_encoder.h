// SPDX-License-Identifier: MIT
/// @brief Encodes the two images of a stereo pair to JPEG at the same time (DESIGN.md §4): the
///        left image on the caller's thread, the right on one persistent worker thread, each with
///        its own TurboJPEG handle. Output buffers are recycled once the link has sent them, so a
///        4K stream does not allocate (and page-fault in) tens of MB per frame. A camera's raw
///        Bayer mosaic is debayered on its side's thread straight into YUV 4:2:0 planes and
///        encoded from them (#34; 4:4:4 and 4:2:2 go through an RGB image, slower).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "robot/cameras/camera_source.h"
#include "robot/clock/clock.h"
#include "robot/video/jpeg_encoder.h"

namespace telesphere::robot::video {

struct EncodedImage {
  std::shared_ptr<const std::vector<std::uint8_t>> jpeg;
  std::int64_t encoded_ns = 0;  ///< host clock when this image's encode finished
  double encode_ms = 0.0;
};

struct EncodedPair {
  EncodedImage left, right;
  JpegSettings settings;  ///< what both were encoded with (settings may change between pairs)
};

class StereoEncoder {
 public:
  StereoEncoder(const clock::Clock& clock, const JpegSettings& settings);
  ~StereoEncoder();
  StereoEncoder(const StereoEncoder&) = delete;
  StereoEncoder& operator=(const StereoEncoder&) = delete;

  /// Encodes both frames (RGB8, Mono8 or one of the 8-bit Bayer mosaics) in parallel.
  /// False with the reason in *error when either fails; `out` is then unspecified.
  bool encode(const cameras::CameraFrame& left, const cameras::CameraFrame& right, EncodedPair& out,
              std::string* error);
  /// The same with `settings` for this pair only (the link's rate control sets quality and
  /// restart markers per frame; settings() stays as it was).
  bool encode(const cameras::CameraFrame& left, const cameras::CameraFrame& right, const JpegSettings& settings,
              EncodedPair& out, std::string* error);

  /// Takes effect from the next encode(). Quality outside 1..100 makes encode() fail.
  void setSettings(const JpegSettings& settings);
  JpegSettings settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::robot::video
