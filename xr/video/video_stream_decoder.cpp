// SPDX-License-Identifier: MIT
/// @brief VideoStreamDecoder: tickets in arrival order around one AvVideoDecoder.
#include "xr/video/video_stream_decoder.h"

#include "xr/video/av_video_decoder.h"

namespace telesphere::xr::video {

VideoStreamDecoder::VideoStreamDecoder(link::VideoCodec codec, int threads) : codec_(codec), threads_(threads) {}

VideoStreamDecoder::~VideoStreamDecoder() = default;

VideoStreamDecoder::Turn VideoStreamDecoder::reserve(std::uint64_t sequence) {
  std::lock_guard lock(mutex_);
  const bool after_gap = !last_sequence_ || sequence != *last_sequence_ + 1;
  last_sequence_ = sequence;
  return {next_ticket_++, after_gap};
}

void VideoStreamDecoder::waitTurn(std::uint64_t ticket, std::unique_lock<std::mutex>& lock) {
  turn_.wait(lock, [&] { return next_turn_ == ticket; });
}

void VideoStreamDecoder::decode(const Turn& turn, std::span<const std::uint8_t> bytes, bool key_frame,
                                int expected_width, int expected_height, render::YuvPlanes& planes,
                                DecodeResult& result) {
  std::unique_lock lock(mutex_);
  waitTurn(turn.ticket, lock);
  if (!decoder_ && open_error_.empty()) {
    decoder_ = AvVideoDecoder::open(codec_, threads_, &open_error_);
    if (decoder_) decoder_->markLost();  // a stream joined part way starts at a key frame
  }
  if (!decoder_) {
    result.error = JpegDecodeError::kUnsupported;
    result.message = open_error_;
  } else {
    if (turn.after_gap) decoder_->markLost();
    std::string why;
    switch (decoder_->decode(bytes, key_frame, planes, &why)) {
      case AvDecodeResult::kFrame:
        if (expected_width > 0 && (planes.width != expected_width || planes.height != expected_height)) {
          result.error = JpegDecodeError::kSizeMismatch;
          result.message = "decoded " + std::to_string(planes.width) + "x" + std::to_string(planes.height) +
                           ", the message says " + std::to_string(expected_width) + "x" +
                           std::to_string(expected_height);
        } else {
          result.error = JpegDecodeError::kNone;
        }
        break;
      case AvDecodeResult::kWaitingForKeyFrame:
        result.error = JpegDecodeError::kCorrupt;
        result.awaiting_key_frame = true;
        result.message = "a frame before it was lost: waiting for a key frame";
        break;
      case AvDecodeResult::kNoFrame:
        result.error = JpegDecodeError::kCorrupt;
        result.message = std::string(link::videoCodecName(codec_)) + ": the decoder held the frame back";
        break;
      case AvDecodeResult::kError:
        result.error = JpegDecodeError::kCorrupt;
        result.message = why;
        break;
    }
  }
  ++next_turn_;
  lock.unlock();
  turn_.notify_all();
}

}  // namespace telesphere::xr::video
