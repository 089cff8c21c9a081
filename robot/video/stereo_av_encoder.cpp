// SPDX-License-Identifier: MIT
/// @brief StereoAvEncoder: two AvVideoEncoders kept in step.
#include "robot/video/stereo_av_encoder.h"

#include <cmath>
#include <future>

#include "robot/video/av_video_encoder.h"
#include "robot/video/frame_to_yuv420.h"

namespace telesphere::robot::video {

struct StereoAvEncoder::Side {
  FrameToYuv420 to_planes;
  cameras::Yuv420Image planes;
  std::unique_ptr<AvVideoEncoder> encoder;
  EncodedVideoFrame packet;

  /// One image: planes, encode, the access unit out; false with the reason.
  bool encode(const clock::Clock& clock, const cameras::CameraFrame& frame, bool key_frame, EncodedAccessUnit& out,
              bool& was_key, std::string* error) {
    const std::int64_t t0 = clock.nowNs();
    if (!to_planes.convert(frame, planes, error)) return false;
    if (!encoder->encode(planes, key_frame, packet, error)) return false;
    out.bytes = std::make_shared<const std::vector<std::uint8_t>>(std::move(packet.bytes));
    out.encoded_ns = clock.nowNs();
    out.encode_ms = static_cast<double>(out.encoded_ns - t0) * 1e-6;
    was_key = packet.key_frame;
    return true;
  }
};

StereoAvEncoder::StereoAvEncoder(const clock::Clock& clock, const StereoAvEncoderOptions& options)
    : clock_(clock), options_(options), bit_rate_bps_(options.bit_rate_bps) {}

StereoAvEncoder::~StereoAvEncoder() = default;

void StereoAvEncoder::requestKeyFrame() { key_frame_requested_ = true; }

void StereoAvEncoder::setBitRate(std::int64_t bit_rate_bps) { bit_rate_bps_ = bit_rate_bps; }

StereoAvEncoderStats StereoAvEncoder::stats() const {
  std::lock_guard lock(stats_mutex_);
  StereoAvEncoderStats s = stats_;
  s.bit_rate_bps = bit_rate_bps_.load();
  return s;
}

bool StereoAvEncoder::open(int width, int height, std::string* error) {
  AvVideoEncoderOptions o;
  o.codec = options_.codec;
  o.width = width;
  o.height = height;
  o.fps = std::max(1, options_.fps);
  o.bit_rate_bps = bit_rate_bps_.load() / 2;
  o.key_frame_interval = options_.key_frame_interval;
  o.threads = options_.threads_per_camera;
  o.prefer_gpu = options_.prefer_gpu;
  auto left = std::make_unique<Side>(), right = std::make_unique<Side>();
  if (!(left->encoder = AvVideoEncoder::open(o, error)) || !(right->encoder = AvVideoEncoder::open(o, error)))
    return false;
  const bool again = left_ != nullptr;
  left_ = std::move(left);
  right_ = std::move(right);
  width_ = width;
  height_ = height;
  opened_rate_bps_ = bit_rate_bps_.load();
  pairs_since_key_ = 0;
  std::lock_guard lock(stats_mutex_);
  stats_.backend = left_->encoder->backend();
  stats_.gpu_fallback_reason = left_->encoder->gpuFallbackReason();
  if (again) ++stats_.reopened;
  return true;
}

bool StereoAvEncoder::encode(const cameras::CameraFrame& left, const cameras::CameraFrame& right,
                             EncodedAccessUnitPair& out, std::string* error) {
  if (options_.codec == link::VideoCodec::kMjpeg) {
    *error = "StereoAvEncoder encodes H.264 and HEVC; MJPEG is StereoEncoder's";
    return false;
  }
  if (left.width != right.width || left.height != right.height) {
    *error = "the two cameras' images differ in size (" + std::to_string(left.width) + "x" + std::to_string(left.height) +
             " and " + std::to_string(right.width) + "x" + std::to_string(right.height) +
             "): one stereo stream needs one size";
    return false;
  }
  const std::int64_t rate = bit_rate_bps_.load();
  const bool in_place = left_ && left_->encoder->changesRateInPlace();
  const bool rate_moved = std::abs(static_cast<double>(rate - opened_rate_bps_)) > 0.1 * static_cast<double>(opened_rate_bps_);
  if (!left_ || left.width != width_ || left.height != height_ || (!in_place && rate_moved)) {
    if (!open(left.width, left.height, error)) return false;
  } else if (rate != opened_rate_bps_ && in_place) {
    left_->encoder->setBitRate(rate / 2);
    right_->encoder->setBitRate(rate / 2);
    opened_rate_bps_ = rate;
  }
  const bool requested = key_frame_requested_.exchange(false);
  // The first pair after opening is a key frame anyway; forcing it keeps both sides' GOPs in step.
  const bool key = requested || pairs_since_key_ == 0 ||
                   pairs_since_key_ >= static_cast<std::uint64_t>(std::max(1, options_.key_frame_interval));
  std::string right_error;
  bool right_key = false, left_key = false;
  auto right_done = std::async(std::launch::async, [&] {
    return right_->encode(clock_, right, key, out.right, right_key, &right_error);
  });
  const bool left_ok = left_->encode(clock_, left, key, out.left, left_key, error);
  const bool right_ok = right_done.get();
  if (!left_ok) return false;
  if (!right_ok) {
    *error = right_error;
    return false;
  }
  out.key_frame = left_key && right_key;
  pairs_since_key_ = out.key_frame ? 1 : pairs_since_key_ + 1;
  std::lock_guard lock(stats_mutex_);
  ++stats_.pairs;
  if (out.key_frame) ++stats_.key_frames;
  if (requested) ++stats_.key_frames_requested;
  return true;
}

}  // namespace telesphere::robot::video
