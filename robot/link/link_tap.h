// SPDX-License-Identifier: MIT
/// @brief A listener on everything that crosses the link at the robot's end: what the server
///        sends (stereo frames with their JPEGs, state, telemetry, health, control replies) and
///        what it receives (head targets, control requests, XR stats and telemetry), for the
///        session recorder (robot/record). Pings, pongs and previews are left out.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link {

class LinkTap {
 public:
  enum class Direction { kSent, kReceived };
  virtual ~LinkTap() = default;
  /// Called on the link's threads right after a message went out or came in (`envelope` with its
  /// sender_clock_ns; for a stereo frame the two JPEGs as sent, null otherwise). Must not block.
  virtual void onLinkMessage(Direction direction, const proto::Envelope& envelope,
                             const std::shared_ptr<const std::vector<std::uint8_t>>& left_jpeg,
                             const std::shared_ptr<const std::vector<std::uint8_t>>& right_jpeg) = 0;
};

}  // namespace telesphere::link
