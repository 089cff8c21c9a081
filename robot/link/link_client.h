// SPDX-License-Identifier: MIT
/// @brief A client's end of the link (telesphere-xr, telesphere-console): stereo frames with
///        latest-frame-wins (a slow consumer drops old frames, never queues them), robot state,
///        health and XR stats (latest wins), telemetry (lossless: every batch queued until taken),
///        preview frames (latest wins), head targets, XR stats and XR telemetry up, control
///        requests, and the ping exchange that keeps the clock offset to the robot (reset when
///        the robot restarts, which the pong's server instance tells).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

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
  /// Image rows [first, end) the link could not deliver and filled mid grey (the media path's
  /// lost bands; never on the ZeroMQ link): the operator side paints them from the last frame.
  std::vector<std::pair<int, int>> left_lost_rows, right_lost_rows;
};

/// A received preview frame (small JPEGs of both cameras); spans valid while `storage` lives.
struct ReceivedPreview {
  proto::PreviewFrame preview;
  std::span<const std::uint8_t> left_jpeg;
  std::span<const std::uint8_t> right_jpeg;
  std::shared_ptr<const void> storage;
};

/// When the client last heard each peer (client clock, steady ns; 0: never), and the robot's
/// process identity as its pongs give it.
struct LinkActivity {
  std::int64_t robot_pong_ns = 0;   ///< last pong: the robot's link is up
  std::int64_t robot_state_ns = 0;  ///< last robot state, health or telemetry
  std::int64_t xr_ns = 0;           ///< last XR stats or telemetry relayed by the robot
  std::uint64_t robot_instance = 0;  ///< 0 before the first pong
  std::uint64_t robot_restarts = 0;  ///< instance changes seen (clock estimate reset each time)
  std::uint64_t telemetry_overflow = 0;  ///< telemetry batches dropped: the queue was full
  /// Handshakes the robot refused on the control channel (DESIGN.md §10), and why, as far as the
  /// protocol tells a client: ZeroMQ passes on a status code, not the robot's text.
  std::uint64_t handshakes_refused = 0;
  std::string refused_reason;  ///< the newest; cleared by the next handshake that succeeds
  /// The reason is the robot's answer to this program's keys (refused key, keys on one side only,
  /// another robot's key), not a connection that broke during the handshake: trying again at
  /// once would give the same answer. A broken handshake never replaces such a reason.
  bool refusal_settled = false;
};

class LinkClient {
 public:
  struct Options {
    bool frames = true;  ///< subscribe to stereo frames (the console may not)
    bool telemetry = false;  ///< queue telemetry batches for takeTelemetry() (the console)
    bool previews = false;   ///< keep preview frames for takeLatestPreview() (the console)
    std::size_t telemetry_queue = 20000;  ///< batches kept untaken; beyond, the oldest go
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
  std::optional<proto::RobotHealth> latestRobotHealth() const;
  /// Every telemetry envelope (robot_telemetry, xr_telemetry) received since the last call, in
  /// arrival order (Options::telemetry; empty otherwise).
  std::vector<proto::Envelope> takeTelemetry();
  /// The newest preview not taken yet (Options::previews).
  std::optional<ReceivedPreview> takeLatestPreview();
  LinkActivity activity() const;

  /// Sends the head target up (the robot keeps only the newest per sender, by t_ns); fills in
  /// sender_instance with this client's instance() unless set. Never blocks.
  void sendHeadTarget(const proto::HeadTarget& target);
  /// This client's random id, fixed for its life (head targets' sender_instance).
  std::uint64_t instance() const;
  void sendXrStats(const proto::XrStats& stats);
  /// Sends a telemetry batch up; the robot republishes it for the console. Never blocks.
  void sendXrTelemetry(const proto::XrTelemetry& telemetry);

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
