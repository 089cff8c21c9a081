// SPDX-License-Identifier: MIT
/// @brief Socket monitors for failed handshakes (see handshake_monitor.h).
#include "robot/link/trust/handshake_monitor.h"

#include <arpa/inet.h>
#include <sys/socket.h>
#include <zmq.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <map>
#include <stdexcept>

namespace telesphere::link::trust {
namespace {

std::int64_t monitorNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::string peerAddress(int fd) {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) return "";
  char text[INET6_ADDRSTRLEN] = {};
  if (address.ss_family == AF_INET)
    inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(&address)->sin_addr, text, sizeof text);
  else if (address.ss_family == AF_INET6)
    inet_ntop(AF_INET6, &reinterpret_cast<sockaddr_in6*>(&address)->sin6_addr, text, sizeof text);
  return text;
}

/// The cause (as counted) and the detail of a handshake that failed before any key was checked.
std::pair<std::string, std::string> whyFailed(std::uint16_t event, std::uint32_t value) {
  if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL) {
    switch (value) {
      case ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH:
        return {"no key", "the peer did not use CURVE (started with --insecure?)"};
      case ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC:
        return {"wrong robot key", "the handshake did not decrypt: the peer holds another robot's .pub"};
      default: return {"bad handshake", "not a telesphere peer: ZeroMQ protocol error " + std::to_string(value)};
    }
  }
  // Often a peer without a key that saw our greeting and hung up before sending its mechanism.
  return {"broken handshake", "the peer closed the connection during the handshake (errno " + std::to_string(value) + ")"};
}

std::atomic<int> monitor_serial{0};

}  // namespace

HandshakeMonitor::HandshakeMonitor(void* zmq_context, const std::vector<std::pair<void*, std::string>>& sockets,
                                   LinkRefusals& refusals)
    : refusals_(refusals) {
  for (const auto& [socket, name] : sockets) {
    const std::string endpoint = "inproc://telesphere-handshakes-" + std::to_string(monitor_serial++);
    if (zmq_socket_monitor(socket, endpoint.c_str(),
                           ZMQ_EVENT_ACCEPTED | ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL |
                               ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL) != 0)
      throw std::runtime_error("link: cannot watch handshakes: " + std::string(zmq_strerror(zmq_errno())));
    void* pair = zmq_socket(zmq_context, ZMQ_PAIR);
    const int linger = 0;
    zmq_setsockopt(pair, ZMQ_LINGER, &linger, sizeof linger);
    zmq_connect(pair, endpoint.c_str());
    watched_.push_back({pair, name});
  }
  thread_ = std::thread([this] { serve(); });
}

HandshakeMonitor::~HandshakeMonitor() {
  running_ = false;
  thread_.join();
  for (auto& w : watched_) zmq_close(w.pair);
}

void HandshakeMonitor::serve() {
  // Per watched socket: the address of each accepted connection (by fd), and a failure waiting
  // for its connection's DISCONNECTED event, which libzmq sends right after it with the fd.
  std::vector<std::map<int, std::string>> addresses(watched_.size());
  std::vector<std::pair<std::string, std::string>> failed(watched_.size());  // cause, detail
  std::vector<zmq_pollitem_t> items;
  for (auto& w : watched_) items.push_back({w.pair, 0, ZMQ_POLLIN, 0});
  while (running_) {
    if (zmq_poll(items.data(), int(items.size()), 100) <= 0) continue;
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (!(items[i].revents & ZMQ_POLLIN)) continue;
      zmq_msg_t first, second;
      zmq_msg_init(&first);
      zmq_msg_init(&second);
      if (zmq_msg_recv(&first, watched_[i].pair, ZMQ_DONTWAIT) < 0) {
        zmq_msg_close(&first);
        zmq_msg_close(&second);
        continue;
      }
      if (zmq_msg_more(&first)) zmq_msg_recv(&second, watched_[i].pair, 0);
      std::uint16_t event = 0;
      std::uint32_t value = 0;
      if (zmq_msg_size(&first) >= 6) {
        std::memcpy(&event, zmq_msg_data(&first), 2);
        std::memcpy(&value, static_cast<const char*>(zmq_msg_data(&first)) + 2, 4);
      }
      zmq_msg_close(&first);
      zmq_msg_close(&second);
      auto& known = addresses[i];
      if (event == ZMQ_EVENT_ACCEPTED) {
        if (known.size() > 4096) known.clear();
        known[int(value)] = peerAddress(int(value));
      } else if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL || event == ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL) {
        failed[i] = whyFailed(event, value);
      } else if (event == ZMQ_EVENT_DISCONNECTED) {
        const auto address = known.find(int(value));
        if (!failed[i].first.empty()) {
          refusals_.count(failed[i].first, failed[i].second + " (" + watched_[i].name + " channel)",
                          address == known.end() ? "" : address->second, "", monitorNowNs());
          failed[i] = {};
        }
        if (address != known.end()) known.erase(address);
      }
    }
  }
}

}  // namespace telesphere::link::trust
