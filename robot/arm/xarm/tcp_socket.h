// SPDX-License-Identifier: MIT
/// @brief A TCP stream socket (POSIX), as the xArm controller's command and report ports need it:
///        connect with a time limit, send all bytes or fail, receive what has arrived within a
///        time limit; a listening socket for the protocol simulator. Errors come back as text
///        naming the address ("127.0.0.1:502: connection refused"), never as exceptions or
///        signals (SIGPIPE is suppressed per call). Not thread-safe per socket except that one
///        thread may send while another receives, and shutdown() may be called from any thread
///        to wake a blocked receive.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace telesphere::xarm {

class TcpSocket {
 public:
  TcpSocket() = default;
  ~TcpSocket();
  TcpSocket(TcpSocket&& other) noexcept;
  TcpSocket& operator=(TcpSocket&& other) noexcept;
  TcpSocket(const TcpSocket&) = delete;
  TcpSocket& operator=(const TcpSocket&) = delete;

  /// Connects to host:port (IPv4 dotted quad or a name) within `timeout`; TCP_NODELAY is set
  /// (commands are small and latency matters). Nothing with the reason on failure.
  static std::optional<TcpSocket> connect(const std::string& host, int port, std::chrono::milliseconds timeout,
                                          std::string* error);

  bool valid() const { return fd_ >= 0; }
  /// "host:port" of the peer, as connected or accepted.
  const std::string& peer() const { return peer_; }

  /// Sends every byte of `data` within `timeout`; false with the reason (peer gone, timeout).
  bool sendAll(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout, std::string* error);

  enum class Received { kData, kTimeout, kClosed, kError };
  /// Waits up to `timeout` for bytes and reads what is there (≤ out.size()) into `out`;
  /// *count is set for kData. kClosed: the peer closed the connection (or shutdown() was called).
  Received receive(std::span<std::uint8_t> out, std::chrono::milliseconds timeout, std::size_t* count,
                   std::string* error);

  /// Ends both directions (wakes a thread blocked in receive with kClosed); the socket stays valid
  /// until destroyed or closed.
  void shutdown();
  void close();

 private:
  friend class TcpListener;
  TcpSocket(int fd, std::string peer) : fd_(fd), peer_(std::move(peer)) {}
  int fd_ = -1;
  std::string peer_;
};

/// A listening socket on 127.0.0.1 or any address (the protocol simulator's ports).
class TcpListener {
 public:
  TcpListener() = default;
  ~TcpListener();
  TcpListener(TcpListener&& other) noexcept;
  TcpListener& operator=(TcpListener&& other) noexcept;
  TcpListener(const TcpListener&) = delete;
  TcpListener& operator=(const TcpListener&) = delete;

  /// Listens on address:port (port 0: the system picks one; see port()). SO_REUSEADDR is set.
  static std::optional<TcpListener> listen(const std::string& address, int port, std::string* error);
  int port() const { return port_; }
  /// Waits up to `timeout` for a connection; nothing on timeout (error empty) or failure (error set).
  std::optional<TcpSocket> accept(std::chrono::milliseconds timeout, std::string* error);
  void close();

 private:
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace telesphere::xarm
