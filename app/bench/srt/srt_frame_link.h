// SPDX-License-Identifier: MIT
/// @brief The media path's datagrams carried by SRT instead (libsrt, live mode: each datagram one
///        message, retransmitted until its play-out deadline, dropped when too late), the design
///        issue #32 weighed against our own framing: `telesphere-bench transport` sends the same
///        frames both ways through the same relay. A listener at the robot's end, a caller at the
///        operator's; libsrt paces and retransmits, we only hand it datagrams (≤ 1456 bytes) and
///        take them out. Benchmark code: the robot and the XR app do not link it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace telesphere::bench::srt {

struct SrtLinkStats {
  std::int64_t packets_sent = 0;          ///< data packets, originals (pktSentUniqueTotal)
  std::int64_t packets_retransmitted = 0; ///< pktRetransTotal
  std::int64_t packets_lost = 0;          ///< seen lost (sender: pktSndLossTotal, receiver: pktRcvLossTotal)
  std::int64_t packets_dropped_late = 0;  ///< too late to play (sender: pktSndDropTotal, receiver: pktRcvDropTotal)
  std::uint64_t bytes_sent = 0;           ///< with retransmissions (byteSentTotal)
  double rtt_ms = 0;                      ///< libsrt's smoothed round trip
};

struct SrtLinkOptions {
  int latency_ms = 120;     ///< the play-out window (SRTO_LATENCY, both ends)
  int payload_bytes = 1456; ///< the largest message (SRTO_PAYLOADSIZE; live mode's maximum)
  int connect_timeout_ms = 3000;
};

/// The robot's end: listens on 127.0.0.1:port (0: any free) and serves the first caller.
class SrtSender {
 public:
  static std::unique_ptr<SrtSender> listen(const SrtLinkOptions& options, std::uint16_t port, std::string* error);
  ~SrtSender();
  SrtSender(const SrtSender&) = delete;
  SrtSender& operator=(const SrtSender&) = delete;

  std::uint16_t port() const { return port_; }
  /// Waits up to timeout_ms for the caller; false with the reason.
  bool accept(int timeout_ms, std::string* error);
  /// One datagram as one message; false with libsrt's reason (no caller, too large, broken).
  bool send(std::span<const std::uint8_t> datagram, std::string* error);
  SrtLinkStats stats() const;

 private:
  SrtSender(int listener, std::uint16_t port) : listener_(listener), port_(port) {}
  int listener_ = -1;
  int socket_ = -1;
  std::uint16_t port_ = 0;
};

/// The operator's end: calls host:port and hands every message to `on_datagram` on its own thread
/// (with the steady-clock time it came out of libsrt), and `on_idle` at least every 10 ms.
class SrtReceiver {
 public:
  using DatagramHandler = std::function<void(std::span<const std::uint8_t> datagram, std::int64_t now_ns)>;
  using IdleHandler = std::function<void(std::int64_t now_ns)>;
  static std::unique_ptr<SrtReceiver> connect(const SrtLinkOptions& options, std::uint16_t port,
                                              DatagramHandler on_datagram, IdleHandler on_idle, std::string* error);
  ~SrtReceiver();
  SrtReceiver(const SrtReceiver&) = delete;
  SrtReceiver& operator=(const SrtReceiver&) = delete;
  SrtLinkStats stats() const;

 private:
  struct Impl;
  explicit SrtReceiver(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::bench::srt
