// SPDX-License-Identifier: MIT
#include "robot/arm/xarm/tcp_socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace telesphere::xarm {
namespace {

std::string describeErrno(int e) { return std::strerror(e); }

/// Waits until fd is readable (POLLIN) or writable (POLLOUT) within timeout; 1 ready, 0 timeout, -1 error.
int waitFor(int fd, short events, std::chrono::milliseconds timeout) {
  pollfd p{fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, int(std::max<std::int64_t>(0, timeout.count())));
    if (r < 0 && errno == EINTR) continue;
    return r < 0 ? -1 : r;
  }
}

bool resolve(const std::string& host, int port, sockaddr_in* out, std::string* error) {
  std::memset(out, 0, sizeof *out);
  out->sin_family = AF_INET;
  out->sin_port = htons(static_cast<std::uint16_t>(port));
  if (::inet_pton(AF_INET, host.c_str(), &out->sin_addr) == 1) return true;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &found); rc != 0 || !found) {
    *error = host + ": cannot resolve the address (" + ::gai_strerror(rc) + ")";
    return false;
  }
  out->sin_addr = reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr;
  ::freeaddrinfo(found);
  return true;
}

}  // namespace

TcpSocket::~TcpSocket() { close(); }
TcpSocket::TcpSocket(TcpSocket&& other) noexcept : fd_(std::exchange(other.fd_, -1)), peer_(std::move(other.peer_)) {}
TcpSocket& TcpSocket::operator=(TcpSocket&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    peer_ = std::move(other.peer_);
  }
  return *this;
}

std::optional<TcpSocket> TcpSocket::connect(const std::string& host, int port, std::chrono::milliseconds timeout,
                                            std::string* error) {
  const std::string where = host + ":" + std::to_string(port);
  sockaddr_in address{};
  if (!resolve(host, port, &address, error)) return std::nullopt;
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) {
    *error = where + ": socket: " + describeErrno(errno);
    return std::nullopt;
  }
  TcpSocket socket(fd, where);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    if (errno != EINPROGRESS) {
      *error = where + ": " + describeErrno(errno);
      return std::nullopt;
    }
    const int ready = waitFor(fd, POLLOUT, timeout);
    if (ready <= 0) {
      *error = where + ": " + (ready == 0 ? "no answer within " + std::to_string(timeout.count()) + " ms"
                                          : describeErrno(errno));
      return std::nullopt;
    }
    int so_error = 0;
    socklen_t length = sizeof so_error;
    ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &so_error, &length);
    if (so_error != 0) {
      *error = where + ": " + describeErrno(so_error);
      return std::nullopt;
    }
  }
  const int flags = ::fcntl(fd, F_GETFL);
  ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return socket;
}

bool TcpSocket::sendAll(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout, std::string* error) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::size_t sent = 0;
  while (sent < data.size()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (fd_ < 0 || waitFor(fd_, POLLOUT, left) <= 0) {
      *error = peer_ + ": " + (fd_ < 0 ? std::string("not connected") : "could not send within " +
                                                                              std::to_string(timeout.count()) + " ms");
      return false;
    }
    const ssize_t n = ::send(fd_, data.data() + sent, data.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
      *error = peer_ + ": send: " + describeErrno(errno);
      return false;
    }
    sent += std::size_t(n);
  }
  return true;
}

TcpSocket::Received TcpSocket::receive(std::span<std::uint8_t> out, std::chrono::milliseconds timeout,
                                       std::size_t* count, std::string* error) {
  if (fd_ < 0) {
    *error = "not connected";
    return Received::kError;
  }
  const int ready = waitFor(fd_, POLLIN, timeout);
  if (ready == 0) return Received::kTimeout;
  if (ready < 0) {
    *error = peer_ + ": poll: " + describeErrno(errno);
    return Received::kError;
  }
  for (;;) {
    const ssize_t n = ::recv(fd_, out.data(), out.size(), MSG_DONTWAIT);
    if (n > 0) {
      *count = std::size_t(n);
      return Received::kData;
    }
    if (n == 0) return Received::kClosed;
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return Received::kTimeout;
    if (errno == ECONNRESET) return Received::kClosed;
    *error = peer_ + ": recv: " + describeErrno(errno);
    return Received::kError;
  }
}

void TcpSocket::shutdown() {
  if (fd_ >= 0) ::shutdown(fd_, SHUT_RDWR);
}

void TcpSocket::close() {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
}

TcpListener::~TcpListener() { close(); }
TcpListener::TcpListener(TcpListener&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), port_(other.port_) {}
TcpListener& TcpListener::operator=(TcpListener&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    port_ = other.port_;
  }
  return *this;
}

std::optional<TcpListener> TcpListener::listen(const std::string& address, int port, std::string* error) {
  const std::string where = address + ":" + std::to_string(port);
  sockaddr_in a{};
  if (!resolve(address, port, &a, error)) return std::nullopt;
  TcpListener listener;
  listener.fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listener.fd_ < 0) {
    *error = where + ": socket: " + describeErrno(errno);
    return std::nullopt;
  }
  const int one = 1;
  ::setsockopt(listener.fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(listener.fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 || ::listen(listener.fd_, 4) != 0) {
    *error = where + ": cannot listen: " + describeErrno(errno);
    return std::nullopt;
  }
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  ::getsockname(listener.fd_, reinterpret_cast<sockaddr*>(&bound), &length);
  listener.port_ = ntohs(bound.sin_port);
  return listener;
}

std::optional<TcpSocket> TcpListener::accept(std::chrono::milliseconds timeout, std::string* error) {
  error->clear();
  if (fd_ < 0) {
    *error = "not listening";
    return std::nullopt;
  }
  const int ready = waitFor(fd_, POLLIN, timeout);
  if (ready <= 0) {
    if (ready < 0) *error = "poll: " + describeErrno(errno);
    return std::nullopt;
  }
  sockaddr_in peer{};
  socklen_t length = sizeof peer;
  const int fd = ::accept4(fd_, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_CLOEXEC);
  if (fd < 0) {
    *error = "accept: " + describeErrno(errno);
    return std::nullopt;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  char text[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &peer.sin_addr, text, sizeof text);
  return TcpSocket(fd, std::string(text) + ":" + std::to_string(ntohs(peer.sin_port)));
}

void TcpListener::close() {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
}

}  // namespace telesphere::xarm
