// SPDX-License-Identifier: MIT
/// @brief The media path (robot/link/media) as a source of stereo frames for the
///        StereoFrameDecoder: a MediaReceiver towards the robot's UDP media port, its frames
///        handed over as link::ReceivedFrame with the rows it filled (DESIGN.md §9).
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "robot/link/link_client.h"
#include "robot/link/media/media_receiver.h"

namespace telesphere::xr::video {

class MediaFrameSource {
 public:
  /// Opens the receiver towards host:port (`repair`: ask for what parity cannot rebuild;
  /// `sealed`: a keyed link, silent until setSealKey); nothing, with the reason in *error.
  static std::unique_ptr<MediaFrameSource> open(const std::string& host, int port, bool repair, bool sealed,
                                                std::string* error);

  /// The newest frame, waiting up to `timeout` (StereoFrameDecoder::Options::frame_source).
  std::optional<link::ReceivedFrame> waitFrame(std::chrono::milliseconds timeout);
  link::media::MediaReceiverStats stats() const { return receiver_->stats(); }
  /// The head target on the media path too (the robot keeps the newest by stamp, whichever way).
  void sendHeadTarget(const link::proto::HeadTarget& target) { receiver_->sendHeadTarget(target); }
  /// The session key of a sealed media path (from the robot over the authenticated control channel).
  void setSealKey(const link::media::MediaSealKey& key) { receiver_->setSealKey(key); }
  bool hasSealKey() const { return receiver_->hasSealKey(); }
  /// The ZeroMQ link's round trip to the robot: how long to wait for a retransmission at first.
  void setRoundTripHintNs(std::int64_t round_trip_ns) { receiver_->setRoundTripHintNs(round_trip_ns); }

 private:
  explicit MediaFrameSource(std::unique_ptr<link::media::MediaReceiver> receiver) : receiver_(std::move(receiver)) {}
  std::unique_ptr<link::media::MediaReceiver> receiver_;
};

}  // namespace telesphere::xr::video
