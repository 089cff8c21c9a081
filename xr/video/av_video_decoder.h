// SPDX-License-Identifier: MIT
/// @brief H.264 and HEVC decoding through FFmpeg's libavcodec (#34) into the same YUV planes the
///        JPEG decoder fills, with low delay (slice threads, no frame reordering). A decoder of
///        predicted frames must see every frame: once told a frame was lost it takes nothing but a
///        key frame (the caller asks the robot for one), so the operator sees the last whole picture
///        instead of a smeared one.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "robot/link/video_codec.h"
#include "xr/render/yuv_planes.h"

namespace telesphere::xr::video {

enum class AvDecodeResult {
  kFrame,               ///< `out` holds the decoded image
  kNoFrame,             ///< accepted, no image out yet
  kWaitingForKeyFrame,  ///< after a loss: refused until a key frame comes
  kError,               ///< the bytes did not decode (reason in *error); wait for a key frame
};

class AvVideoDecoder {
 public:
  /// nullptr with the reason when this libavcodec has no decoder for `codec` (or it is MJPEG).
  static std::unique_ptr<AvVideoDecoder> open(link::VideoCodec codec, int threads, std::string* error);
  ~AvVideoDecoder();
  AvVideoDecoder(const AvVideoDecoder&) = delete;
  AvVideoDecoder& operator=(const AvVideoDecoder&) = delete;

  /// Decodes one access unit; `key_frame` as the sender flagged it.
  AvDecodeResult decode(std::span<const std::uint8_t> bytes, bool key_frame, render::YuvPlanes& out,
                        std::string* error);
  /// A frame never arrived: take nothing but a key frame from now on.
  void markLost();
  bool waitingForKeyFrame() const;

 private:
  struct Impl;
  explicit AvVideoDecoder(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::xr::video
