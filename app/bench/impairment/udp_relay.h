// SPDX-License-Identifier: MIT
/// @brief An in-process UDP relay on loopback that puts an ImpairedPath in each direction: a
///        client sends to the relay's port instead of the server's; the relay forwards what it
///        receives to the server through the client → server path and the server's replies back
///        to the last client address seen through the server → client path, on the steady clock.
///        For the UDP media paths' tests and `telesphere-bench network`. One thread; datagrams up
///        to 65 507 bytes.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "app/bench/impairment/impaired_path.h"

namespace telesphere::bench::impairment {

struct UdpRelayOptions {
  std::uint16_t listen_port = 0;   ///< 0: any free port (see UdpRelay::port)
  std::uint16_t server_port = 0;   ///< the server, on 127.0.0.1
  PathOptions to_server;           ///< client → server
  PathOptions to_client;           ///< server → client
  /// Called on the relay's thread for every packet as it leaves a path (to_client: towards the
  /// client), with its times on the relay's clock (ns since it started); may be empty.
  std::function<void(const PathPacket& packet, bool to_client)> on_arrival;
};

struct UdpRelayStats {
  PathStats to_server, to_client;
  std::uint64_t send_errors = 0;
};

class UdpRelay {
 public:
  /// Binds and starts; nothing, with the reason (the port, errno's text) in *error.
  static std::unique_ptr<UdpRelay> start(const UdpRelayOptions& options, std::string* error);
  ~UdpRelay();
  UdpRelay(const UdpRelay&) = delete;
  UdpRelay& operator=(const UdpRelay&) = delete;

  /// The port clients send to.
  std::uint16_t port() const { return port_; }
  UdpRelayStats stats() const;

 private:
  UdpRelay(const UdpRelayOptions& options, int client_fd, int server_fd, std::uint16_t port);
  void run();

  UdpRelayOptions options_;
  int client_fd_ = -1;  ///< bound to the listen port: clients' datagrams in, replies out
  int server_fd_ = -1;  ///< connected to the server
  std::uint16_t port_ = 0;
  mutable std::mutex mutex_;
  ImpairedPath to_server_, to_client_;
  std::uint64_t send_errors_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace telesphere::bench::impairment
