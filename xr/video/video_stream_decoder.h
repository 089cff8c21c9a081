// SPDX-License-Identifier: MIT
/// @brief One camera's H.264/HEVC stream decoded in the order its frames arrived (#34), on
///        whichever DecodePool worker takes each frame: the receive thread takes a ticket per frame
///        and a worker decodes only when its ticket is next, so a predicted frame never meets the
///        decoder before the frame it was predicted from. A frame the link lost (a gap in the link
///        sequence of the frames reserved) makes the decoder take nothing but a key frame after it
///        (the last whole picture stays on screen meanwhile). Also used on one thread (the replay).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>

#include "robot/link/video_codec.h"
#include "xr/video/decode_pool.h"

namespace telesphere::xr::video {

class AvVideoDecoder;

class VideoStreamDecoder {
 public:
  /// `threads`: slice threads of the decoder. The decoder opens with the first frame (an error then
  /// comes back in that frame's result).
  VideoStreamDecoder(link::VideoCodec codec, int threads);
  ~VideoStreamDecoder();
  VideoStreamDecoder(const VideoStreamDecoder&) = delete;
  VideoStreamDecoder& operator=(const VideoStreamDecoder&) = delete;

  link::VideoCodec codec() const { return codec_; }
  /// A frame's place in the stream: its turn, and whether frames before it never arrived.
  struct Turn {
    std::uint64_t ticket = 0;
    bool after_gap = false;  ///< its link sequence does not follow the last one's (or it is the first)
  };
  /// The next frame's turn, in arrival order (the receive thread; `sequence` as the link numbered
  /// the frame). Every turn taken must be decoded, or later ones wait for ever: take it when the
  /// frame goes to the pool (or, decoding on one thread, right before decode()).
  Turn reserve(std::uint64_t sequence);
  /// Waits for the turn, decodes `bytes` into `planes` and says how in `result`: error kNone;
  /// kCorrupt with the reason, or with awaiting_key_frame after a gap; kSizeMismatch when the
  /// image is not expected_width × expected_height (0: any size); kUnsupported when this
  /// libavcodec lacks the decoder.
  void decode(const Turn& turn, std::span<const std::uint8_t> bytes, bool key_frame, int expected_width,
              int expected_height, render::YuvPlanes& planes, DecodeResult& result);

 private:
  void waitTurn(std::uint64_t ticket, std::unique_lock<std::mutex>& lock);

  const link::VideoCodec codec_;
  const int threads_;
  std::mutex mutex_;
  std::condition_variable turn_;
  std::uint64_t next_ticket_ = 0;  ///< handed out by reserve()
  std::uint64_t next_turn_ = 0;    ///< whose turn it is
  std::optional<std::uint64_t> last_sequence_;  ///< the last reserved frame's link sequence
  std::unique_ptr<AvVideoDecoder> decoder_;
  std::string open_error_;
};

}  // namespace telesphere::xr::video
