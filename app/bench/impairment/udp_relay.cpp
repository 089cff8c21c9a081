// SPDX-License-Identifier: MIT
#include "app/bench/impairment/udp_relay.h"

#include "app/bench/impairment/steady_now.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <time.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

namespace telesphere::bench::impairment {
namespace {

sockaddr_in loopback(std::uint16_t port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return address;
}

}  // namespace

std::unique_ptr<UdpRelay> UdpRelay::start(const UdpRelayOptions& options, std::string* error) {
  for (const PathOptions* path : {&options.to_server, &options.to_client}) {
    if (const std::string why = checkPathOptions(*path); !why.empty()) {
      if (error) *error = "relay path: " + why;
      return nullptr;
    }
  }
  const auto fail = [&](const std::string& what, int a, int b) -> std::unique_ptr<UdpRelay> {
    if (error) *error = what + ": " + std::strerror(errno);
    if (a >= 0) ::close(a);
    if (b >= 0) ::close(b);
    return nullptr;
  };
  const int client_fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (client_fd < 0) return fail("relay: socket", -1, -1);
  const sockaddr_in listen_at = loopback(options.listen_port);
  if (::bind(client_fd, reinterpret_cast<const sockaddr*>(&listen_at), sizeof listen_at) != 0)
    return fail("relay: bind 127.0.0.1:" + std::to_string(options.listen_port), client_fd, -1);
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  ::getsockname(client_fd, reinterpret_cast<sockaddr*>(&bound), &length);
  const int server_fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (server_fd < 0) return fail("relay: socket", client_fd, -1);
  const sockaddr_in server = loopback(options.server_port);
  if (::connect(server_fd, reinterpret_cast<const sockaddr*>(&server), sizeof server) != 0)
    return fail("relay: connect 127.0.0.1:" + std::to_string(options.server_port), client_fd, server_fd);
  // Room for bursts while the relay's thread is busy (the kernel may grant less).
  const int buffer_bytes = 4 << 20;
  for (const int fd : {client_fd, server_fd}) ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buffer_bytes, sizeof buffer_bytes);
  return std::unique_ptr<UdpRelay>(new UdpRelay(options, client_fd, server_fd, ntohs(bound.sin_port)));
}

UdpRelay::UdpRelay(const UdpRelayOptions& options, int client_fd, int server_fd, std::uint16_t port)
    : options_(options),
      client_fd_(client_fd),
      server_fd_(server_fd),
      port_(port),
      to_server_(options.to_server),
      to_client_(options.to_client) {
  thread_ = std::thread([this] { run(); });
}

UdpRelay::~UdpRelay() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  ::close(client_fd_);
  ::close(server_fd_);
}

UdpRelayStats UdpRelay::stats() const {
  std::lock_guard lock(mutex_);
  return {to_server_.stats(), to_client_.stats(), send_errors_};
}

void UdpRelay::run() {
  // Path times are ns since the relay started, so rate steps count from then.
  const std::int64_t start_ns = steadyNowNs();
  std::vector<std::uint8_t> buffer(65536);
  std::optional<sockaddr_in> client;
  while (!stop_) {
    std::int64_t wait_ns = 5'000'000;  // wake often enough to see stop_
    {
      std::lock_guard lock(mutex_);
      const std::int64_t now_ns = steadyNowNs() - start_ns;
      for (const auto next : {to_server_.nextArrivalNs(), to_client_.nextArrivalNs()})
        if (next) wait_ns = std::clamp<std::int64_t>(*next - now_ns, 0, wait_ns);
    }
    pollfd fds[2] = {{client_fd_, POLLIN, 0}, {server_fd_, POLLIN, 0}};
    const timespec wait{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    ::ppoll(fds, 2, &wait, nullptr);
    std::lock_guard lock(mutex_);
    // Everything waiting, not one datagram per wake-up: a relay that lags adds its own queue.
    while (fds[0].revents & POLLIN) {
      sockaddr_in from{};
      socklen_t length = sizeof from;
      const ssize_t n = ::recvfrom(client_fd_, buffer.data(), buffer.size(), MSG_DONTWAIT,
                                   reinterpret_cast<sockaddr*>(&from), &length);
      if (n < 0) break;
      client = from;
      to_server_.offer({buffer.begin(), buffer.begin() + n}, steadyNowNs() - start_ns);
    }
    while (fds[1].revents & POLLIN) {
      const ssize_t n = ::recv(server_fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
      if (n < 0) break;
      to_client_.offer({buffer.begin(), buffer.begin() + n}, steadyNowNs() - start_ns);
    }
    const std::int64_t now_ns = steadyNowNs() - start_ns;
    for (const PathPacket& packet : to_server_.arrivedBy(now_ns)) {
      if (::send(server_fd_, packet.bytes.data(), packet.bytes.size(), 0) < 0) ++send_errors_;
      if (options_.on_arrival) options_.on_arrival(packet, false);
    }
    for (const PathPacket& packet : to_client_.arrivedBy(now_ns)) {
      if (options_.on_arrival) options_.on_arrival(packet, true);
      if (!client || ::sendto(client_fd_, packet.bytes.data(), packet.bytes.size(), 0,
                              reinterpret_cast<const sockaddr*>(&*client), sizeof *client) < 0)
        ++send_errors_;
    }
  }
}

}  // namespace telesphere::bench::impairment
