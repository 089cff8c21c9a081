// SPDX-License-Identifier: MIT
/// @brief Counts the handshakes that fail before any key is checked (DESIGN.md §10): a peer
///        without a key (plain ZeroMQ against a CURVE socket), one that holds the wrong robot key
///        (the handshake does not decrypt), and bytes that are not ZeroMQ at all. libzmq reports
///        them through socket monitors; the peer's address is taken when the connection is
///        accepted (best effort: a connection closed before the monitor reads it stays unnamed).
#pragma once

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "robot/link/trust/link_refusals.h"

namespace telesphere::link::trust {

class HandshakeMonitor {
 public:
  /// Watches `sockets` (named for the log by `names`) of `zmq_context`; call from the thread that
  /// created the sockets, before it hands them to another thread.
  HandshakeMonitor(void* zmq_context, const std::vector<std::pair<void*, std::string>>& sockets,
                   LinkRefusals& refusals);
  ~HandshakeMonitor();
  HandshakeMonitor(const HandshakeMonitor&) = delete;
  HandshakeMonitor& operator=(const HandshakeMonitor&) = delete;

 private:
  void serve();

  struct Watched {
    void* pair = nullptr;
    std::string name;
  };
  std::vector<Watched> watched_;
  LinkRefusals& refusals_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace telesphere::link::trust
