// SPDX-License-Identifier: MIT
/// @brief Where the link's four sockets live: base_port + 0 stereo frames (PUB), + 1 robot state
///        and republished XR stats (PUB), + 2 uplink of head targets and XR stats (PULL on the
///        robot), + 3 control requests and pings (ROUTER on the robot), and + 4 the UDP media
///        path (frames paced to the link's rate). The robot binds; the XR app and the console
///        connect, in any order, and reconnect on their own. With credentials (DESIGN.md §10) every
///        ZeroMQ socket is CURVE: authenticated and encrypted; without, plain TCP (--insecure).
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "robot/link/trust/link_credentials.h"

namespace telesphere::link {

struct LinkEndpoints {
  std::string host = "127.0.0.1";  ///< where clients connect; the server binds on all interfaces
  int base_port = 5760;
  trust::LinkCredentials credentials;  ///< none: insecure (programs allow it only with --insecure)

  std::string connect(int offset) const { return "tcp://" + host + ":" + std::to_string(base_port + offset); }
  std::string bind(int offset) const { return "tcp://*:" + std::to_string(base_port + offset); }

  static constexpr int kFrames = 0;
  static constexpr int kState = 1;
  static constexpr int kUplink = 2;
  static constexpr int kControl = 3;
  /// UDP, not ZeroMQ: the media path of the Internet link (robot/link/media, DESIGN.md §9).
  static constexpr int kMedia = 4;
};

/// The steady clock every stamp of this process uses, in ns.
inline std::int64_t linkNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace telesphere::link
