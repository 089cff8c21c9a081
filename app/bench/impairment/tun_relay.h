// SPDX-License-Identifier: MIT
/// @brief An impaired path on IP packets (DESIGN.md §9): two TUN devices, "ts-near" in the calling
///        thread's network namespace (address kNearAddress, peer kFarAddress) and "ts-far" in a
///        namespace of the relay's own (the other way round), and between them one ImpairedPath
///        each way on the steady clock. Anything the kernel sends between the two addresses —
///        TCP with its real retransmissions, congestion control and head-of-line blocking, or
///        UDP — crosses the relay's delay, jitter, loss and bottleneck, as over the Internet.
///        TCP's congestion control is pinned on both routes (these machines default to BBR; a
///        robot PC usually runs CUBIC). Needs CAP_NET_ADMIN; the caller should be in a private
///        namespace of its own (enterPrivateNetworkNamespace) so nothing lands on the machine's
///        network. One thread; packets up to the TUN's MTU (1500).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "app/bench/impairment/impaired_path.h"

namespace telesphere::bench::impairment {

struct TunRelayOptions {
  PathOptions to_far;   ///< near → far (the robot's side → the operator's: where the bottleneck sits)
  PathOptions to_near;  ///< far → near
  std::string congestion_control = "cubic";  ///< on both ends' routes; "": the namespaces' default
  /// Called on the relay's thread for every packet as it leaves a path, with its times on the
  /// relay's clock (ns since it started); may be empty.
  std::function<void(const PathPacket& packet, bool to_far)> on_arrival;
};

struct TunRelayStats {
  PathStats to_far, to_near;
  std::uint64_t write_errors = 0;
};

class TunRelay {
 public:
  static constexpr const char* kNearAddress = "10.77.0.1";
  static constexpr const char* kFarAddress = "10.77.0.2";

  /// Makes both devices and the far namespace and starts; nothing, with the reason in *error.
  static std::unique_ptr<TunRelay> start(const TunRelayOptions& options, std::string* error);
  ~TunRelay();
  TunRelay(const TunRelay&) = delete;
  TunRelay& operator=(const TunRelay&) = delete;

  /// The far side's network namespace (runInNetworkNamespace starts the operator's programs there).
  int farNamespace() const { return far_ns_fd_; }
  TunRelayStats stats() const;

 private:
  TunRelay(const TunRelayOptions& options, int near_fd, int far_fd, int far_ns_fd);
  void run();

  TunRelayOptions options_;
  int near_fd_ = -1, far_fd_ = -1, far_ns_fd_ = -1;
  mutable std::mutex mutex_;
  ImpairedPath to_far_, to_near_;
  std::uint64_t write_errors_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace telesphere::bench::impairment
