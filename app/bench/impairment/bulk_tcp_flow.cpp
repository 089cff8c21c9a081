// SPDX-License-Identifier: MIT
/// @brief BulkTcpFlow: listen in the far namespace, connect, send and sink until stopped.
#include "app/bench/impairment/bulk_tcp_flow.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "app/bench/impairment/network_namespace.h"

namespace telesphere::bench::impairment {

std::unique_ptr<BulkTcpFlow> BulkTcpFlow::start(int far_ns_fd, const std::string& far_address, std::uint16_t port,
                                                std::string* error) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  if (::inet_pton(AF_INET, far_address.c_str(), &address.sin_addr) != 1) {
    *error = "bulk flow: not an IPv4 address: " + far_address;
    return nullptr;
  }
  int listener = -1;
  std::string why;
  if (!runInNetworkNamespace(far_ns_fd, [&] {
        listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        const int one = 1;
        ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        if (::bind(listener, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
            ::listen(listener, 1) != 0) {
          why = std::string("bulk flow: listen on ") + far_address + ":" + std::to_string(port) + ": " + std::strerror(errno);
          ::close(listener);
          listener = -1;
        }
      }, error))
    return nullptr;
  if (listener < 0) {
    *error = why;
    return nullptr;
  }
  const int sender = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (::connect(sender, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    *error = std::string("bulk flow: connect: ") + std::strerror(errno);
    ::close(sender);
    ::close(listener);
    return nullptr;
  }
  pollfd ready{listener, POLLIN, 0};
  const int sink = ::poll(&ready, 1, 5000) == 1 ? ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC) : -1;
  ::close(listener);
  if (sink < 0) {
    *error = "bulk flow: the sink accepted nothing";
    ::close(sender);
    return nullptr;
  }
  return std::unique_ptr<BulkTcpFlow>(new BulkTcpFlow(sender, sink));
}

BulkTcpFlow::BulkTcpFlow(int sender_fd, int sink_fd) : sender_fd_(sender_fd), sink_fd_(sink_fd) {
  sender_ = std::thread([this] {
    const std::vector<std::uint8_t> block(64 * 1024, 0x5A);
    pollfd fd{sender_fd_, POLLOUT, 0};
    while (!stop_)
      if (::poll(&fd, 1, 50) == 1 && ::send(sender_fd_, block.data(), block.size(), MSG_NOSIGNAL | MSG_DONTWAIT) < 0 &&
          errno != EAGAIN)
        break;
  });
  sink_ = std::thread([this] {
    std::vector<std::uint8_t> buffer(64 * 1024);
    pollfd fd{sink_fd_, POLLIN, 0};
    while (!stop_) {
      if (::poll(&fd, 1, 50) != 1) continue;
      const ssize_t n = ::recv(sink_fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
      if (n == 0 || (n < 0 && errno != EAGAIN)) break;
      if (n > 0) received_ += static_cast<std::uint64_t>(n);
    }
  });
}

BulkTcpFlow::~BulkTcpFlow() {
  stop_ = true;
  sender_.join();
  sink_.join();
  ::close(sender_fd_);
  ::close(sink_fd_);
}

}  // namespace telesphere::bench::impairment
