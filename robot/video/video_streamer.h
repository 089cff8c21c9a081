// SPDX-License-Identifier: MIT
/// @brief The robot side of the video path (DESIGN.md §4): takes stereo pairs, encodes both
///        images in parallel, attaches each camera's pose T_robot_cam at its capture time (from
///        the joint-state buffer; the fixed calibrated pose, flagged as such, when the buffer
///        cannot say) and the generation of the calibration that gave it, and publishes the frame
///        on the link with its capture and encode stamps.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "robot/head/calibration_in_use.h"
#include "robot/clock/clock.h"
#include "robot/head/joint_state_buffer.h"
#include "robot/link/link_server.h"
#include "robot/link/media/media_sender.h"
#include "robot/video/stereo_av_encoder.h"
#include "robot/video/stereo_encoder.h"
#include "robot/video/stream_settings_controller.h"
#include "robot/stereo/stereo_pairer.h"
#include "robot/telemetry/telemetry_batcher.h"

namespace telesphere::robot::video {

/// Both cameras' T_robot_cam at their capture times (CalibrationInUse::posesAt on the robot).
using StereoPosesAt = std::function<head::StereoCameraPoses(std::int64_t left_capture_ns, std::int64_t right_capture_ns)>;

struct VideoStreamerConfig {
  JpegSettings jpeg;
  /// Gets one SentFrame sample per frame sent (null: no telemetry).
  telemetry::TelemetryBatcher* telemetry = nullptr;
  /// Called with every pair sent and its sequence (the console's preview); must not block.
  std::function<void(const stereo::StereoFrame&, std::uint64_t sequence)> on_sent;
  /// The Internet link's media path (null: the ZeroMQ link only). Every JPEG then carries a
  /// restart marker per MCU row, and every frame goes to both links; while the media path has a
  /// receiver, frame rate, scale and quality follow its send rate (StreamSettingsController,
  /// never above `jpeg.quality` or the cameras' rate).
  link::media::MediaSender* media = nullptr;
  /// MJPEG (each image a JPEG, `jpeg`'s settings), or H.264/HEVC through `video` (#34) at
  /// video.bit_rate_bps: on the media path, while it has a receiver, at most that and otherwise
  /// kVideoBudgetShare of its budget (frame rate and scale stay nominal).
  link::VideoCodec codec = link::VideoCodec::kMjpeg;
  StereoAvEncoderOptions video;
  /// For the adaptation: nominal_fps (the cameras'), the scales, the quality floor;
  /// pixels_per_frame and nominal_quality are taken from the first pair and `jpeg`.
  StreamSettingsLimits adaptive;
};

struct VideoStreamerStats {
  std::uint64_t frames_sent = 0;
  std::uint64_t bytes_sent = 0;         ///< both images' encoded bytes, every frame sent
  std::uint64_t encode_failures = 0;
  std::uint64_t poses_from_joints = 0;  ///< camera images whose pose came from joint states
  std::uint64_t poses_fixed = 0;        ///< … from the fixed calibration
  double encode_ms_last = 0.0;          ///< wall time of the last pair's (parallel) encode
  std::int64_t capture_to_sent_ns_last = 0;
  std::uint32_t exposure_us_last[2] = {0, 0};  ///< [left, right], of the last pair sent
  int width = 0, height = 0;                   ///< of the last pair's images (as sent)
  std::string last_error;
  std::uint64_t frames_skipped_for_rate = 0;   ///< pairs not sent: the link's rate asked for fewer
  std::uint64_t media_refused = 0;             ///< frames the media path could not take
  StreamSettings stream;                       ///< the last pair's settings (fps, scale, quality, why)
  bool stream_adapted = false;                 ///< stream is the media path's, not the nominal one
  StreamSettingsStats stream_decisions;
  link::VideoCodec codec = link::VideoCodec::kMjpeg;  ///< what the frames carry
  StereoAvEncoderStats video;                          ///< H.264/HEVC: key frames, backend
};

class VideoStreamer {
 public:
  /// H.264/HEVC on the media path aim at this share of its budget (rate control meets its
  /// target on average, not per frame), never below kMinVideoBitRateBps.
  static constexpr double kVideoBudgetShare = 0.9;
  static constexpr double kMinVideoBitRateBps = 200e3;

  VideoStreamer(stereo::StereoPairSource& pairs, link::LinkServer& server, const clock::Clock& clock,
                StereoPosesAt poses, const VideoStreamerConfig& config);
  ~VideoStreamer();
  VideoStreamer(const VideoStreamer&) = delete;
  VideoStreamer& operator=(const VideoStreamer&) = delete;

  /// Starts the streaming thread (the pair source must be started by the caller).
  void start();
  void stop();

  /// One pair: encode and publish (what the thread does per pair); false on an encode failure.
  bool publish(const stereo::StereoFrame& pair);

  void setJpegSettings(const JpegSettings& settings) { encoder_.setSettings(settings); }
  /// H.264/HEVC: the next pair is a key-frame pair (the operator lost a frame); false (nothing
  /// to do) for MJPEG, whose every image stands alone. Any thread.
  bool requestKeyFrame();
  /// The codec from the next pair on (the supervisor's choice; a new H.264/HEVC stream starts with
  /// a key frame). Any thread.
  void setCodec(link::VideoCodec codec) { codec_ = codec; }
  link::VideoCodec codec() const { return codec_.load(); }
  /// H.264/HEVC: the encoders' target, both cameras together (0 for MJPEG).
  std::int64_t videoBitRateBps() const { return codec() != link::VideoCodec::kMjpeg ? config_.video.bit_rate_bps : 0; }
  JpegSettings jpegSettings() const { return encoder_.settings(); }
  VideoStreamerStats stats() const;
  /// The media path's sender (null: the ZeroMQ link only).
  link::media::MediaSender* mediaSender() const { return config_.media; }

 private:
  void run();
  /// The H.264/HEVC encoder for `codec` (made, or made again for another codec, here; null for
  /// MJPEG, whose pairs StereoEncoder encodes).
  std::shared_ptr<StereoAvEncoder> avEncoderFor(link::VideoCodec codec);
  /// H.264/HEVC on the media path: sets `encoder`'s rate from the path's budget (down at once
  /// on a fall of a fifth, else every 250 ms at most); kBitRate while below nominal.
  StreamLimitedBy followBudget(StereoAvEncoder& encoder, double budget_bps, std::int64_t now_ns);

  stereo::StereoPairSource& pairs_;
  link::LinkServer& server_;
  const clock::Clock& clock_;
  StereoPosesAt poses_;
  VideoStreamerConfig config_;
  StereoEncoder encoder_;
  std::atomic<link::VideoCodec> codec_;
  mutable std::mutex av_encoder_mutex_;
  std::shared_ptr<StereoAvEncoder> av_encoder_;  ///< H.264/HEVC (null for MJPEG); under av_encoder_mutex_
  std::optional<StreamSettingsController> stream_settings_;
  std::int64_t video_rate_bps_ = 0;  ///< what followBudget set last on this encoder (0: nothing yet)
  std::int64_t video_rate_changed_ns_ = 0;
  std::int64_t last_sent_ns_ = 0;
  std::int64_t last_pair_ns_ = 0;
  double pair_interval_ns_ = 0;  ///< averaged time between pairs
  std::uint64_t sequence_ = 0;
  mutable std::mutex stats_mutex_;
  VideoStreamerStats stats_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace telesphere::robot::video
