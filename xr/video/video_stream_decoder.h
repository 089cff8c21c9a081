// SPDX-License-Identifier: MIT
/// @brief One camera's H.264/HEVC stream decoded in the order its frames arrived (#34), on
///        whichever DecodePool worker takes each frame: the receive thread takes a ticket per frame
///        and a worker decodes only when its ticket is next, so a predicted frame never meets the
///        decoder before the frame it was predicted from. A frame the link lost (a gap the receive
///        thread saw) is passed along with the next ticket: the decoder then takes nothing but a
///        key frame (the last whole picture stays on screen meanwhile).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
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
  /// The next frame's turn, in arrival order (the receive thread). Every ticket taken must be
  /// decoded, or later ones wait for ever: take it when the frame goes to the pool.
  std::uint64_t reserve();
  /// On a pool worker: waits for the ticket's turn, decodes `bytes` into `planes` and says how in
  /// `result` (error kCorrupt with the reason, or awaiting_key_frame). `lost_before`: frames
  /// before this one never arrived.
  void decode(std::uint64_t ticket, std::span<const std::uint8_t> bytes, bool key_frame, bool lost_before,
              render::YuvPlanes& planes, DecodeResult& result);

 private:
  void waitTurn(std::uint64_t ticket, std::unique_lock<std::mutex>& lock);

  const link::VideoCodec codec_;
  const int threads_;
  std::mutex mutex_;
  std::condition_variable turn_;
  std::uint64_t next_ticket_ = 0;  ///< handed out by reserve()
  std::uint64_t next_turn_ = 0;    ///< whose turn it is
  std::unique_ptr<AvVideoDecoder> decoder_;
  std::string open_error_;
};

}  // namespace telesphere::xr::video
