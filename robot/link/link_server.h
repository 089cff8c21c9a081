// SPDX-License-Identifier: MIT
/// @brief The robot's end of the link (telesphere-robot): publishes stereo frames and robot state,
///        telemetry, health and preview frames for the console; takes head targets (latest wins),
///        XR stats and XR telemetry from the uplink (the last two republished on the state
///        channel, so the console hears the XR app through the robot); answers control requests
///        and pings. Any number of clients connect, leave and come back without a restart.
///
///        The state channel is lossless as long as a subscriber keeps up: its queue holds
///        kStateQueueMessages per subscriber (tens of seconds of telemetry), and telemetry
///        batches are numbered so a subscriber can count what it lost when it did not.
///
///        With credentials (LinkEndpoints::credentials, DESIGN.md §10) every socket is a CURVE
///        server: only keys in allowed/ finish a handshake (ZapAuthenticator), viewers are kept off
///        the frames channel, uplink messages pass for the seated operator only, control requests
///        for supervisors only; every refusal is counted (trustHealth) and answered where the
///        socket has a way back (control replies carry the reason).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "robot/link/link_endpoints.h"
#include "robot/link/link_stats.h"
#include "robot/link/link_tap.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link {

/// Encoded image bytes shared with ZeroMQ until they are on the wire (no copy).
using SharedBytes = std::shared_ptr<const std::vector<std::uint8_t>>;

class LinkServer {
 public:
  using ControlHandler = std::function<proto::ControlReply(const proto::ControlRequest&)>;
  /// Messages queued per state subscriber before the newest are dropped (ZeroMQ's PUB HWM).
  static constexpr int kStateQueueMessages = 20000;

  /// How long a control request that came before the first handler waits for one.
  static constexpr std::chrono::milliseconds kControlWaitAtStart{15000};

  /// Binds the four sockets; throws std::runtime_error naming the endpoint when a port is taken.
  /// The ports open before the program has built what answers control requests: a request that
  /// comes before the first setControlHandler waits for it (at most `control_wait_at_start`, then
  /// it is answered "still starting").
  explicit LinkServer(const LinkEndpoints& endpoints,
                      std::chrono::milliseconds control_wait_at_start = kControlWaitAtStart);
  ~LinkServer();
  LinkServer(const LinkServer&) = delete;
  LinkServer& operator=(const LinkServer&) = delete;

  /// Publishes [envelope, left, right]; sets the jpeg sizes, stamps.sent_ns and the envelope.
  /// Never blocks: a subscriber that cannot keep up loses frames at its end, not ours.
  /// Returns the sent_ns stamped into the frame.
  std::int64_t publishStereoFrame(proto::StereoFrame frame, SharedBytes left_jpeg, SharedBytes right_jpeg);
  void publishRobotState(const proto::RobotState& state);
  void publishTelemetry(const proto::RobotTelemetry& telemetry);
  void publishHealth(const proto::RobotHealth& health);
  /// Publishes [envelope, left, right] on the state channel (sizes set here). Never blocks.
  void publishPreview(proto::PreviewFrame preview, SharedBytes left_jpeg, SharedBytes right_jpeg);

  /// Random per process, answered in every Pong: clients see a restart as a new value.
  std::uint64_t instance() const;

  /// The newest head target received, if any: the last one that was newer (by t_ns) than
  /// everything its sender instance had sent before.
  std::optional<proto::HeadTarget> latestHeadTarget() const;
  /// A head target that came another way (the UDP media path, robot/link/media): kept as the
  /// latest under the same rule as the uplink's. False when its sender already sent a newer one.
  bool offerHeadTarget(const proto::HeadTarget& target);
  /// Called on the link's thread for every control request; the reply goes back to its sender.
  /// Before the first handler requests wait for it (see the constructor); once it is set to null
  /// again they are answered {ok: false, error: "the robot is shutting down"}.
  void setControlHandler(ControlHandler handler);

  /// Called on the link's thread after a supervisor handed the operator seat over (the new
  /// holder's name, empty when freed): the robot ends the media session of the one before.
  void setOperatorSeatHandler(std::function<void(const std::string& name)> handler);

  /// Everything sent and received from now on also goes to `tap` (null: nobody). A call in
  /// flight keeps the tap it started with alive.
  void setTap(std::shared_ptr<LinkTap> tap);

  LinkStatsSnapshot stats() const;
  /// Who may use the link and who was refused (DESIGN.md §10), for the health report.
  proto::LinkTrustHealth trustHealth() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::link
