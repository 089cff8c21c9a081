// SPDX-License-Identifier: MIT
/// @brief A competing bulk TCP flow across a TunRelay (DESIGN.md §9): a sender on the near side
///        writes as fast as TCP lets it to a sink listening in the relay's far namespace, from
///        start until the object goes away, as a download beside the robot's video would. Its
///        congestion control is the route's (the relay pins CUBIC). Two threads; every wait bounded.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

namespace telesphere::bench::impairment {

class BulkTcpFlow {
 public:
  /// Listens on `far_address:port` in the namespace `far_ns_fd` and connects to it from the
  /// calling thread's namespace; nothing, with the reason in *error.
  static std::unique_ptr<BulkTcpFlow> start(int far_ns_fd, const std::string& far_address, std::uint16_t port,
                                            std::string* error);
  ~BulkTcpFlow();
  BulkTcpFlow(const BulkTcpFlow&) = delete;
  BulkTcpFlow& operator=(const BulkTcpFlow&) = delete;

  /// Bytes the sink has received so far.
  std::uint64_t bytesReceived() const { return received_.load(); }

 private:
  BulkTcpFlow(int sender_fd, int sink_fd);

  int sender_fd_ = -1, sink_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> received_{0};
  std::thread sender_, sink_;
};

}  // namespace telesphere::bench::impairment
