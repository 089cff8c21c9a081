// SPDX-License-Identifier: MIT
/// @brief Encodes the two images of a stereo pair as H.264 or HEVC (#34): one AvVideoEncoder per
///        camera, the right one working on a thread of its own while the left one works on the
///        caller's. Both streams start together and force their key frames together (every
///        key_frame_interval pairs, and on the operator's request after a loss), so one key-frame
///        pair lets the operator's decoders start again. Any camera image (Bayer, RGB, grey) goes
///        in; the encoders are opened on the first pair and again when the size changes.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "robot/cameras/camera_source.h"
#include "robot/clock/clock.h"
#include "robot/link/video_codec.h"

namespace telesphere::robot::video {

struct StereoAvEncoderOptions {
  link::VideoCodec codec = link::VideoCodec::kH264;
  std::int64_t bit_rate_bps = 20'000'000;  ///< both cameras together (each gets half)
  int fps = 45;                            ///< the cameras' rate (the encoders' rate control)
  int key_frame_interval = 90;             ///< pairs between key frames: the recovery bound without a request
  int threads_per_camera = 1;              ///< slice threads of each encoder
  bool prefer_gpu = false;                 ///< NVENC first (else the CPU encoder, with the reason)
};

/// One camera's access unit.
struct EncodedAccessUnit {
  std::shared_ptr<const std::vector<std::uint8_t>> bytes;
  std::int64_t encoded_ns = 0;  ///< host clock when this image's encode finished
  double encode_ms = 0.0;
};

struct EncodedAccessUnitPair {
  EncodedAccessUnit left, right;
  bool key_frame = false;  ///< both are key frames (IDR)
};

struct StereoAvEncoderStats {
  std::uint64_t pairs = 0;
  std::uint64_t key_frames = 0;             ///< key-frame pairs sent (first, interval, requested, reopened)
  std::uint64_t key_frames_requested = 0;   ///< requests taken (several before one pair count once)
  std::uint64_t reopened = 0;               ///< encoders opened again (size or HEVC rate change)
  std::int64_t bit_rate_bps = 0;            ///< the target now, both cameras (setBitRate's last)
  std::string backend;                      ///< "libx264", "hevc_nvenc", …; empty before the first pair
  std::string gpu_fallback_reason;
};

class StereoAvEncoder {
 public:
  /// Refuses MJPEG and bad rates with the reason in the first encode().
  StereoAvEncoder(const clock::Clock& clock, const StereoAvEncoderOptions& options);
  ~StereoAvEncoder();
  StereoAvEncoder(const StereoAvEncoder&) = delete;
  StereoAvEncoder& operator=(const StereoAvEncoder&) = delete;

  /// Encodes both images (same size; even width and height of at least 16 px); false with the
  /// reason when either fails, `out` then unspecified.
  bool encode(const cameras::CameraFrame& left, const cameras::CameraFrame& right, EncodedAccessUnitPair& out,
              std::string* error);
  /// The next pair is a key-frame pair. Any thread.
  void requestKeyFrame();
  /// The target for both cameras together from the next pair (libx264 and NVENC change it in
  /// place; libx265 cannot, so its encoders are opened again, starting with a key frame, when the
  /// rate moves by more than 10 %). Any thread.
  void setBitRate(std::int64_t bit_rate_bps);
  StereoAvEncoderStats stats() const;
  const StereoAvEncoderOptions& options() const { return options_; }

 private:
  struct Side;
  bool open(int width, int height, std::string* error);

  const clock::Clock& clock_;
  StereoAvEncoderOptions options_;
  std::unique_ptr<Side> left_, right_;
  int width_ = 0, height_ = 0;
  std::int64_t opened_rate_bps_ = 0;
  std::uint64_t pairs_since_key_ = 0;
  std::atomic<bool> key_frame_requested_{false};
  std::atomic<std::int64_t> bit_rate_bps_;
  mutable std::mutex stats_mutex_;
  StereoAvEncoderStats stats_;
};

}  // namespace telesphere::robot::video
