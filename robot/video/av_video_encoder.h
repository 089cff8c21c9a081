// SPDX-License-Identifier: MIT
/// @brief H.264 and HEVC encoding through FFmpeg's libavcodec (#34), tuned for latency: no
///        B-frames, zero-latency settings (a packet out for every image in, nothing held back),
///        slice threads, a key frame every `key_frame_interval` images and whenever the receiver
///        asks (it lost a frame). x264 and x265 on the CPU; NVENC first where `prefer_gpu` is set
///        and the machine has an NVIDIA GPU and driver, else the CPU encoder with the reason kept.
///        Takes the YUV 4:2:0 planes the camera path makes (JFIF full range, flagged as such).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "robot/cameras/yuv420_image.h"
#include "robot/link/video_codec.h"

namespace telesphere::robot::video {

struct AvVideoEncoderOptions {
  link::VideoCodec codec = link::VideoCodec::kH264;  ///< H.264 or HEVC (MJPEG is JpegEncoder's)
  int width = 0, height = 0;                         ///< px, even
  int fps = 45;                                      ///< images a second (for the rate control)
  std::int64_t bit_rate_bps = 20'000'000;            ///< target, constant over about one image
  int key_frame_interval = 90;                       ///< images between key frames (the recovery bound)
  int threads = 2;                                   ///< slice threads (0: libavcodec picks)
  bool prefer_gpu = false;                           ///< NVENC first, the CPU encoder if it cannot open
};

/// One encoded image: an access unit (Annex B) the decoder takes whole.
struct EncodedVideoFrame {
  std::vector<std::uint8_t> bytes;
  bool key_frame = false;
  std::int64_t index = 0;  ///< which image in (0, 1, …): the frame this packet is
};

class AvVideoEncoder {
 public:
  /// Opens the encoder; nullptr with the reason in *error (codec missing from this libavcodec,
  /// bad size or rate).
  static std::unique_ptr<AvVideoEncoder> open(const AvVideoEncoderOptions& options, std::string* error);
  ~AvVideoEncoder();
  AvVideoEncoder(const AvVideoEncoder&) = delete;
  AvVideoEncoder& operator=(const AvVideoEncoder&) = delete;

  /// Encodes one image (its size as opened); `key_frame` forces a key frame (IDR). With the
  /// zero-latency settings `out` holds this image's packet; false with the reason on failure, or
  /// when the encoder held the image back (counted in held_back()).
  bool encode(const cameras::Yuv420Image& image, bool key_frame, EncodedVideoFrame& out, std::string* error);

  /// Changes the target rate from the next image on (the link's rate controller): libx264 and
  /// NVENC reconfigure at the next image. FFmpeg 5.1's libx265 wrapper does not reconfigure, so
  /// for HEVC on the CPU the new rate waits for the encoder to be opened again (not done yet).
  void setBitRate(std::int64_t bit_rate_bps);
  /// Whether setBitRate() takes effect in place (libx264, NVENC); false for libx265, whose rate
  /// changes only when the encoder is opened again.
  bool changesRateInPlace() const;

  /// "libx264", "libx265", "h264_nvenc", "hevc_nvenc": what encodes.
  std::string backend() const;
  /// Why the GPU encoder was not used (empty when it is, or was not asked for).
  std::string gpuFallbackReason() const;
  /// Images given to the encoder that did not come out as a packet at once (0 at zero latency).
  std::int64_t heldBack() const;

 private:
  struct Impl;
  explicit AvVideoEncoder(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::robot::video
