// SPDX-License-Identifier: MIT
/// @brief A client's end of the link (telesphere-xr, telesphere-console): stereo frames with
///        latest-frame-wins (a slow consumer drops old frames, never queues them), robot state,
///        XR stats, head targets and stats up, control requests, and the ping exchange that
///        keeps the clock offset to the robot.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "robot/link/clock_sync.h"
#include "robot/link/link_endpoints.h"
#include "robot/link/link_stats.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link {

/// A received stereo frame; the JPEG spans stay valid while `storage` lives (no copy was made).
struct ReceivedFrame {
  proto::StereoFrame frame;  ///< stamps.received_ns set in the client's clock
  std::span<const std::uint8_t> left_jpeg;
  std::span<const std::uint8_t> right_jpeg;
  std::shared_ptr<const void> storage;
};

class LinkClient {
 public:
  struct Options {
    bool frames = true;  ///< subscribe to stereo frames (the console may not)
    std::chrono::milliseconds ping_period{200};
  };

  LinkClient(const LinkEndpoints& endpoints, Options options);
  explicit LinkClient(const LinkEndpoints& endpoints) : LinkClient(endpoints, Options{}) {}
  ~LinkClient();
  LinkClient(const LinkClient&) = delete;
  LinkClient& operator=(const LinkClient&) = delete;

  /// The newest frame not taken yet (older ones were dropped as superseded), or nothing.
  std::optional<ReceivedFrame> takeLatestFrame();
  /// Like takeLatestFrame, waiting up to `timeout` for one to arrive.
  std::optional<ReceivedFrame> waitForFrame(std::chrono::milliseconds timeout);

  std::optional<proto::RobotState> latestRobotState() const;
  std::optional<proto::XrStats> latestXrStats() const;

  /// Sends the head target up (the robot keeps only the newest). Never blocks.
  void sendHeadTarget(const proto::HeadTarget& target);
  void sendXrStats(const proto::XrStats& stats);

  /// Sends a control request and waits for its reply; nothing on timeout (robot not there).
  std::optional<proto::ControlReply> request(proto::ControlRequest request,
                                             std::chrono::milliseconds timeout);

  const ClockSync& clock() const;
  LinkStatsSnapshot stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::link
