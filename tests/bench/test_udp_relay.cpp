// SPDX-License-Identifier: MIT
/// @brief UdpRelay with real UDP sockets on loopback: an echo server behind the relay sees the
///        datagrams the paths let through, no earlier than their delay, and the relay's counts
///        match what the endpoints saw. Every wait is bounded.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "app/bench/impairment/udp_relay.h"

namespace telesphere::bench::impairment {
namespace {

constexpr std::int64_t kMs = 1'000'000;

int boundUdp(std::uint16_t* port) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  *port = ntohs(address.sin_port);
  return fd;
}

/// Echoes every datagram back to its sender and counts them, until stopped.
class EchoServer {
 public:
  EchoServer() : fd_(boundUdp(&port_)), thread_([this] { run(); }) {}
  ~EchoServer() {
    stop_ = true;
    thread_.join();
    ::close(fd_);
  }
  std::uint16_t port() const { return port_; }
  int received() const { return received_; }

 private:
  void run() {
    char buffer[2048];
    while (!stop_) {
      pollfd fds{fd_, POLLIN, 0};
      if (::poll(&fds, 1, 10) <= 0) continue;
      sockaddr_in from{};
      socklen_t length = sizeof from;
      const ssize_t n = ::recvfrom(fd_, buffer, sizeof buffer, 0, reinterpret_cast<sockaddr*>(&from), &length);
      if (n < 0) continue;
      ++received_;
      ::sendto(fd_, buffer, static_cast<std::size_t>(n), 0, reinterpret_cast<sockaddr*>(&from), length);
    }
  }
  std::uint16_t port_ = 0;
  int fd_;
  std::atomic<bool> stop_{false};
  std::atomic<int> received_{0};
  std::thread thread_;
};

struct Client {
  Client() : fd(boundUdp(&port)) {}
  ~Client() { ::close(fd); }
  void sendTo(std::uint16_t to, std::uint32_t value) const {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(to);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::sendto(fd, &value, sizeof value, 0, reinterpret_cast<sockaddr*>(&address), sizeof address);
  }
  /// The next datagram within timeout_ms; nothing after it.
  std::optional<std::uint32_t> receive(int timeout_ms) const {
    pollfd fds{fd, POLLIN, 0};
    if (::poll(&fds, 1, timeout_ms) <= 0) return std::nullopt;
    std::uint32_t value = 0;
    if (::recv(fd, &value, sizeof value, 0) != sizeof value) return std::nullopt;
    return value;
  }
  std::uint16_t port = 0;
  int fd;
};

TEST(UdpRelay, EachDirectionAddsItsDelay) {
  EchoServer server;
  UdpRelayOptions options;
  options.server_port = server.port();
  options.to_server.one_way_delay_ns = 20 * kMs;
  options.to_client.one_way_delay_ns = 30 * kMs;
  std::string error;
  const auto relay = UdpRelay::start(options, &error);
  ASSERT_TRUE(relay) << error;
  Client client;
  for (std::uint32_t i = 0; i < 10; ++i) {
    const auto sent = std::chrono::steady_clock::now();
    client.sendTo(relay->port(), i);
    const auto echo = client.receive(2000);
    const auto rtt = std::chrono::steady_clock::now() - sent;
    ASSERT_TRUE(echo) << "no echo of " << i;
    EXPECT_EQ(*echo, i);
    EXPECT_GE(rtt, std::chrono::milliseconds(50)) << i;  // never before both delays
  }
  const UdpRelayStats stats = relay->stats();
  EXPECT_EQ(stats.to_server.delivered, 10u);
  EXPECT_EQ(stats.to_client.delivered, 10u);
  EXPECT_EQ(stats.send_errors, 0u);
}

TEST(UdpRelay, WhatTheLossTakesNeverArrivesAndIsCounted) {
  EchoServer server;
  UdpRelayOptions options;
  options.server_port = server.port();
  options.to_server.loss = {0.3, 1, 9};
  std::string error;
  const auto relay = UdpRelay::start(options, &error);
  ASSERT_TRUE(relay) << error;
  Client client;
  int echoes = 0;
  for (std::uint32_t i = 0; i < 300; ++i) {
    client.sendTo(relay->port(), i);
    if (i % 10 == 9)
      while (client.receive(50)) ++echoes;  // drain, bounded
  }
  while (client.receive(200)) ++echoes;
  const UdpRelayStats stats = relay->stats();
  EXPECT_EQ(stats.to_server.offered, 300u);
  EXPECT_EQ(stats.to_server.lost + stats.to_server.delivered, 300u);
  EXPECT_EQ(static_cast<int>(stats.to_server.delivered), server.received());
  EXPECT_EQ(echoes, server.received());
  EXPECT_NEAR(stats.to_server.lost / 300.0, 0.3, 0.1);
}

TEST(UdpRelay, ATakenPortOrBadOptionsAreRefusedWithTheReason) {
  std::uint16_t taken = 0;
  const int fd = boundUdp(&taken);
  UdpRelayOptions options;
  options.listen_port = taken;
  options.server_port = 9;
  std::string error;
  EXPECT_FALSE(UdpRelay::start(options, &error));
  EXPECT_NE(error.find(std::to_string(taken)), std::string::npos) << error;
  ::close(fd);
  options = {};
  options.to_client.jitter_ns = -5;
  EXPECT_FALSE(UdpRelay::start(options, &error));
  EXPECT_NE(error.find("jitter"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::bench::impairment
