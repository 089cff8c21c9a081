// SPDX-License-Identifier: MIT
/// @brief TunRelay: devices, addresses, pinned routes, and the relay loop.
#include "app/bench/impairment/tun_relay.h"

#include <fcntl.h>
#include <linux/if_tun.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include "app/bench/impairment/network_namespace.h"
#include "app/bench/impairment/steady_now.h"

namespace telesphere::bench::impairment {
namespace {

/// A TUN device `name` in the calling thread's namespace, up, `address` with `peer`, the route to
/// the peer with `congestion_control`; its descriptor (non-blocking), or −1 with *error.
int openTun(const char* name, const char* address, const char* peer, const std::string& congestion_control,
            std::string* error) {
  const int fd = ::open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    *error = std::string("/dev/net/tun: ") + std::strerror(errno);
    return -1;
  }
  ifreq request{};
  request.ifr_flags = IFF_TUN | IFF_NO_PI;
  std::strncpy(request.ifr_name, name, IFNAMSIZ - 1);
  if (::ioctl(fd, TUNSETIFF, &request) != 0) {
    *error = std::string("TUN device ") + name + ": " + std::strerror(errno) + " (needs CAP_NET_ADMIN)";
    ::close(fd);
    return -1;
  }
  std::vector<std::vector<std::string>> commands = {
      {"addr", "add", address, "peer", peer, "dev", name},
      {"link", "set", name, "up"},
  };
  if (!congestion_control.empty())
    commands.push_back({"route", "replace", peer, "dev", name, "proto", "kernel", "scope", "link", "src", address,
                        "congctl", congestion_control});
  for (const auto& command : commands)
    if (!runIp(command, error)) {
      ::close(fd);
      return -1;
    }
  return fd;
}

}  // namespace

std::unique_ptr<TunRelay> TunRelay::start(const TunRelayOptions& options, std::string* error) {
  for (const PathOptions* path : {&options.to_far, &options.to_near})
    if (const std::string why = checkPathOptions(*path); !why.empty()) {
      *error = "relay path: " + why;
      return nullptr;
    }
  const int near_fd = openTun("ts-near", kNearAddress, kFarAddress, options.congestion_control, error);
  if (near_fd < 0) return nullptr;
  const int far_ns = makeNetworkNamespace(error);
  if (far_ns < 0) {
    ::close(near_fd);
    return nullptr;
  }
  int far_fd = -1;
  std::string far_error;
  const bool entered = runInNetworkNamespace(
      far_ns, [&] { far_fd = openTun("ts-far", kFarAddress, kNearAddress, options.congestion_control, &far_error); },
      error);
  if (!entered || far_fd < 0) {
    if (entered) *error = far_error;
    ::close(near_fd);
    ::close(far_ns);
    return nullptr;
  }
  return std::unique_ptr<TunRelay>(new TunRelay(options, near_fd, far_fd, far_ns));
}

TunRelay::TunRelay(const TunRelayOptions& options, int near_fd, int far_fd, int far_ns_fd)
    : options_(options),
      near_fd_(near_fd),
      far_fd_(far_fd),
      far_ns_fd_(far_ns_fd),
      to_far_(options.to_far),
      to_near_(options.to_near) {
  thread_ = std::thread([this] { run(); });
}

TunRelay::~TunRelay() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  ::close(near_fd_);
  ::close(far_fd_);
  ::close(far_ns_fd_);
}

TunRelayStats TunRelay::stats() const {
  std::lock_guard lock(mutex_);
  return {to_far_.stats(), to_near_.stats(), write_errors_};
}

void TunRelay::run() {
  const std::int64_t start_ns = steadyNowNs();
  std::vector<std::uint8_t> buffer(65536);
  while (!stop_) {
    std::int64_t wait_ns = 5'000'000;  // wake often enough to see stop_
    {
      std::lock_guard lock(mutex_);
      const std::int64_t now_ns = steadyNowNs() - start_ns;
      for (const auto next : {to_far_.nextArrivalNs(), to_near_.nextArrivalNs()})
        if (next) wait_ns = std::clamp<std::int64_t>(*next - now_ns, 0, wait_ns);
    }
    pollfd fds[2] = {{near_fd_, POLLIN, 0}, {far_fd_, POLLIN, 0}};
    const timespec wait{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    ::ppoll(fds, 2, &wait, nullptr);
    std::lock_guard lock(mutex_);
    // Everything waiting, not one packet per wake-up: a relay that lags adds its own queue.
    for (int side = 0; side < 2; ++side) {
      if (!(fds[side].revents & POLLIN)) continue;
      ImpairedPath& path = side == 0 ? to_far_ : to_near_;
      for (;;) {
        const ssize_t n = ::read(fds[side].fd, buffer.data(), buffer.size());
        if (n <= 0) break;
        path.offer({buffer.begin(), buffer.begin() + n}, steadyNowNs() - start_ns);
      }
    }
    const std::int64_t now_ns = steadyNowNs() - start_ns;
    for (const PathPacket& packet : to_far_.arrivedBy(now_ns)) {
      if (::write(far_fd_, packet.bytes.data(), packet.bytes.size()) < 0) ++write_errors_;
      if (options_.on_arrival) options_.on_arrival(packet, true);
    }
    for (const PathPacket& packet : to_near_.arrivedBy(now_ns)) {
      if (::write(near_fd_, packet.bytes.data(), packet.bytes.size()) < 0) ++write_errors_;
      if (options_.on_arrival) options_.on_arrival(packet, false);
    }
  }
}

}  // namespace telesphere::bench::impairment
