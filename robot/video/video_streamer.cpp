// SPDX-License-Identifier: MIT
/// @brief VideoStreamer: pair → parallel encode → StereoFrame message → link.
#include "robot/video/video_streamer.h"

#include "robot/video/media_link_sample.h"

#include "robot/link/proto_enums.h"

#include "robot/link/link_pose.h"
#include "robot/video/frame_scaler.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

namespace telesphere::robot::video {
namespace {

link::proto::ChromaSubsampling protoSubsampling(const cameras::CameraFrame& frame, ChromaSubsampling s) {
  if (frame.format == cameras::PixelFormat::kMono8) return link::proto::CHROMA_GRAY;
  return link::toProto(s);
}

}  // namespace

VideoStreamer::VideoStreamer(stereo::StereoPairSource& pairs, link::LinkServer& server, const clock::Clock& clock,
                             StereoPosesAt poses, const VideoStreamerConfig& config)
    : pairs_(pairs),
      server_(server),
      clock_(clock),
      poses_(std::move(poses)),
      config_(config),
      encoder_(clock, config.jpeg),
      codec_(config.codec) {}

std::shared_ptr<StereoAvEncoder> VideoStreamer::avEncoderFor(link::VideoCodec codec) {
  std::lock_guard lock(av_encoder_mutex_);
  if (codec == link::VideoCodec::kMjpeg) {
    av_encoder_.reset();
  } else if (!av_encoder_ || av_encoder_->options().codec != codec) {
    StereoAvEncoderOptions options = config_.video;
    options.codec = codec;
    av_encoder_ = std::make_shared<StereoAvEncoder>(clock_, options);
    video_rate_bps_ = 0;  // a new encoder starts at the nominal rate (this thread only, as followBudget)
  }
  return av_encoder_;
}

bool VideoStreamer::requestKeyFrame() {
  std::lock_guard lock(av_encoder_mutex_);
  if (!av_encoder_) return codec() != link::VideoCodec::kMjpeg;  // the next pair is a new stream's first
  av_encoder_->requestKeyFrame();
  return true;
}

StreamLimitedBy VideoStreamer::followBudget(StereoAvEncoder& encoder, double budget_bps, std::int64_t now_ns) {
  const auto nominal = static_cast<double>(config_.video.bit_rate_bps);
  // A margin under the budget: the encoder's rate control meets its target on average, not per frame.
  const double wanted = std::clamp(kVideoBudgetShare * budget_bps, kMinVideoBitRateBps, nominal);
  const auto now_rate = static_cast<double>(video_rate_bps_ > 0 ? video_rate_bps_ : config_.video.bit_rate_bps);
  // Down at once when the budget fell by more than a fifth; otherwise at most every 250 ms and
  // by more than 5 % (HEVC's encoder opens again on a change of more than 10 %).
  const bool fell = wanted < 0.8 * now_rate;
  const bool due = now_ns - video_rate_changed_ns_ >= 250'000'000 && std::abs(wanted - now_rate) > 0.05 * now_rate;
  if (video_rate_bps_ == 0 || fell || due) {
    video_rate_bps_ = static_cast<std::int64_t>(wanted);
    video_rate_changed_ns_ = now_ns;
    encoder.setBitRate(video_rate_bps_);
  }
  return static_cast<double>(video_rate_bps_) < 0.95 * nominal ? StreamLimitedBy::kBitRate : StreamLimitedBy::kNothing;
}

VideoStreamer::~VideoStreamer() { stop(); }

void VideoStreamer::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void VideoStreamer::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

VideoStreamerStats VideoStreamer::stats() const {
  std::lock_guard lock(stats_mutex_);
  VideoStreamerStats s = stats_;
  s.codec = codec();
  std::lock_guard encoder_lock(av_encoder_mutex_);
  if (av_encoder_) s.video = av_encoder_->stats();
  return s;
}

void VideoStreamer::run() {
  while (running_) {
    if (auto pair = pairs_.nextPair(std::chrono::milliseconds(50))) publish(*pair);
  }
}

bool VideoStreamer::publish(const stereo::StereoFrame& pair) {
  const std::int64_t start_ns = clock_.nowNs();
  // The rate pairs come at (a camera or this PC slower than nominal): the adaptation uses it.
  if (last_pair_ns_ != 0) {
    const double dt = static_cast<double>(start_ns - last_pair_ns_);
    pair_interval_ns_ = pair_interval_ns_ == 0 ? dt : 0.9 * pair_interval_ns_ + 0.1 * dt;
  }
  last_pair_ns_ = start_ns;
  JpegSettings jpeg = encoder_.settings();
  StreamSettings stream;
  stream.fps = config_.adaptive.nominal_fps;
  stream.quality = jpeg.quality;
  const bool adapted = config_.media && config_.media->hasReceiver();
  cameras::CameraFrame left = pair.left, right = pair.right;
  if (config_.media) jpeg.restart_mcu_rows = 1;
  const link::VideoCodec codec = codec_.load();
  const std::shared_ptr<StereoAvEncoder> av = avEncoderFor(codec);
  if (av && config_.media) {
    // H.264/HEVC on the media path: every frame at full size (each predicted from the one
    // before), the encoder's rate following the path's budget; a chain the sender broke (a
    // dropped frame, a new receiver) restarts at a key frame.
    if (config_.media->takeKeyFrameRequest()) av->requestKeyFrame();
    if (adapted) {
      stream.limited_by = followBudget(*av, config_.media->payloadBudgetBps(), start_ns);
      stream.predicted_bits_per_s = static_cast<double>(video_rate_bps_);
    }
  } else if (adapted) {
    if (!stream_settings_) {
      StreamSettingsLimits limits = config_.adaptive;
      limits.pixels_per_frame = static_cast<double>(pair.left.width) * pair.left.height +
                                static_cast<double>(pair.right.width) * pair.right.height;
      limits.nominal_quality = jpeg.quality;
      limits.min_quality = std::min(limits.min_quality, jpeg.quality);
      stream_settings_.emplace(limits);
    }
    if (pair_interval_ns_ > 0) stream_settings_->setSourceFps(1e9 / pair_interval_ns_);
    stream = stream_settings_->decide(config_.media->payloadBudgetBps(), start_ns);
    // The cameras' period, less half of it: a 45 Hz camera asked for 15 Hz sends every third pair.
    const double period_ns = 1e9 / stream.fps - 0.5e9 / config_.adaptive.nominal_fps;
    if (last_sent_ns_ != 0 && static_cast<double>(start_ns - last_sent_ns_) < period_ns) {
      std::lock_guard lock(stats_mutex_);
      ++stats_.frames_skipped_for_rate;
      return true;
    }
    jpeg.quality = stream.quality;
    left = scaleFrame(pair.left, stream.scale);
    right = scaleFrame(pair.right, stream.scale);
  }
  last_sent_ns_ = start_ns;
  EncodedPair encoded;
  std::string error;
  bool key_frame = false;
  bool encoded_ok = false;
  if (av) {
    EncodedAccessUnitPair units;
    encoded_ok = av->encode(left, right, units, &error);
    if (encoded_ok) {
      encoded.left = {units.left.bytes, units.left.encoded_ns, units.left.encode_ms};
      encoded.right = {units.right.bytes, units.right.encoded_ns, units.right.encode_ms};
      key_frame = units.key_frame;
    }
  } else {
    encoded_ok = encoder_.encode(left, right, jpeg, encoded, &error);
  }
  if (!encoded_ok) {
    std::lock_guard lock(stats_mutex_);
    if (stats_.encode_failures++ % 100 == 0)  // one line per 100, not one per frame
      std::cerr << "telesphere-robot: frame dropped, encode failed: " << error << '\n';
    stats_.last_error = error;
    return false;
  }
  const JpegSettings& settings = encoded.settings;  // not settings(): it may have changed since

  link::proto::StereoFrame message;
  message.set_sequence(++sequence_);
  std::uint64_t from_joints = 0, fixed = 0;
  const head::StereoCameraPoses poses = poses_ ? poses_(pair.left.capture_ns, pair.right.capture_ns) : head::StereoCameraPoses{};
  message.set_calibration_generation(poses.calibration_generation);
  const auto describe = [&](const cameras::CameraFrame& frame, cameras::CameraSide side, link::proto::CameraImage* image) {
    image->set_capture_ns(frame.capture_ns);
    image->set_width(static_cast<std::uint32_t>(frame.width));
    image->set_height(static_cast<std::uint32_t>(frame.height));
    image->set_subsampling(av ? link::proto::CHROMA_420 : protoSubsampling(frame, settings.subsampling));
    image->set_exposure_us(frame.exposure_us);
    image->set_camera_sequence(frame.sequence);
    if (av) {
      image->set_codec(link::toProto(codec));
      image->set_key_frame(key_frame);
    }
    const bool left = side == cameras::CameraSide::kLeft;
    if (left ? poses.measured_l : poses.measured_r) {
      image->set_pose_source(link::proto::POSE_SOURCE_JOINT_BUFFER);
      ++from_joints;
    } else {
      image->set_pose_source(link::proto::POSE_SOURCE_FIXED_CALIBRATION);
      ++fixed;
    }
    link::toLinkPose(left ? poses.T_robot_cam_l : poses.T_robot_cam_r, image->mutable_t_robot_cam());
  };
  describe(left, cameras::CameraSide::kLeft, message.mutable_left());
  describe(right, cameras::CameraSide::kRight, message.mutable_right());
  // The pair is as old as its older image; it is encoded when both are.
  message.mutable_stamps()->set_capture_ns(std::min(pair.left.capture_ns, pair.right.capture_ns));
  message.mutable_stamps()->set_encoded_ns(std::max(encoded.left.encoded_ns, encoded.right.encoded_ns));
  const std::int64_t capture_ns = message.stamps().capture_ns();
  const std::int64_t encoded_ns = message.stamps().encoded_ns();
  if (config_.media) {
    link::proto::StreamState* state = message.mutable_stream();
    state->set_adapted(adapted && stream.limited_by != StreamLimitedBy::kNothing);
    state->set_fps(stream.fps);
    state->set_scale(stream.scale);
    state->set_quality(static_cast<std::uint32_t>(jpeg.quality));
    state->set_limited_by(streamLimitedByName(stream.limited_by));
    state->set_target_mbit(config_.media->targetBps() * 1e-6);
  }
  const std::uint64_t sequence = message.sequence();
  bool media_refused = false;
  if (config_.media) {
    link::proto::StereoFrame media_message = message;
    media_message.mutable_stamps()->set_sent_ns(link::linkNowNs());
    std::string media_error;
    if (!config_.media->sendFrame(media_message, *encoded.left.jpeg, *encoded.right.jpeg, &media_error)) {
      media_refused = true;
      error = media_error;
    }
  }
  const std::size_t jpeg_bytes = encoded.left.jpeg->size() + encoded.right.jpeg->size();
  if (adapted && !av) stream_settings_->observeFrame(stream, jpeg_bytes);
  const std::int64_t link_sent_ns =
      server_.publishStereoFrame(std::move(message), encoded.left.jpeg, encoded.right.jpeg);

  const std::int64_t sent_ns = clock_.nowNs();
  if (config_.telemetry) {
    link::proto::SentFrame sent;
    sent.set_sequence(sequence);
    sent.set_capture_ns(capture_ns);
    sent.set_encoded_ns(encoded_ns);
    sent.set_sent_ns(link_sent_ns);  // the stamp the frame itself carries
    sent.set_jpeg_bytes(static_cast<std::uint32_t>(encoded.left.jpeg->size() + encoded.right.jpeg->size()));
    if (config_.media) *sent.mutable_media() = mediaLinkSample(config_.media->stats(), adapted, stream, jpeg.quality);
    config_.telemetry->addFrame(sent);
  }
  if (config_.on_sent) config_.on_sent(pair, sequence);
  std::lock_guard lock(stats_mutex_);
  ++stats_.frames_sent;
  stats_.bytes_sent += jpeg_bytes;
  stats_.poses_from_joints += from_joints;
  stats_.poses_fixed += fixed;
  stats_.encode_ms_last = static_cast<double>(
      std::max(encoded.left.encoded_ns, encoded.right.encoded_ns) - start_ns) * 1e-6;
  stats_.capture_to_sent_ns_last = sent_ns - capture_ns;
  stats_.exposure_us_last[0] = pair.left.exposure_us;
  stats_.exposure_us_last[1] = pair.right.exposure_us;
  stats_.width = left.width;
  stats_.height = left.height;
  stats_.stream = stream;
  stats_.stream_adapted = adapted;
  if (stream_settings_) stats_.stream_decisions = stream_settings_->stats();
  if (media_refused) {
    if (stats_.media_refused++ % 100 == 0) std::cerr << "telesphere-robot: the media path refused a frame: " << error << '\n';
    stats_.last_error = error;
  }
  return true;
}

}  // namespace telesphere::robot::video
