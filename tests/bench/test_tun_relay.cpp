// SPDX-License-Identifier: MIT
/// @brief TunRelay on real kernel TCP: in a private network namespace, a TCP stream from the
///        near side to a server in the relay's far namespace crosses 20 ms each way, 1 % loss and
///        a 20 Mbit/s bottleneck. Every byte arrives in order (the kernel retransmits what the
///        relay lost), the handshake takes at least the round trip, the transfer no less than the
///        bottleneck allows, the connection runs the pinned congestion control (CUBIC, not this
///        machine's BBR), and the relay's counts match: every data segment of the stream that the
///        relay lost was sent again. The relay also carries traffic nobody resends (UDP datagrams
///        this test sends beside the stream, and what the kernel sends by itself on new devices,
///        such as IPv6 router solicitations), so its own loss count is only an upper bound. Needs CAP_NET_ADMIN: root runs it (CI
///        does); without, it is skipped and says why. Every wait is bounded.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <linux/tcp.h>  // its tcp_info has tcpi_data_segs_out, glibc's does not
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "app/bench/impairment/network_namespace.h"
#include "app/bench/impairment/tun_relay.h"

namespace telesphere::bench::impairment {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::uint16_t kPort = 29400;
constexpr int kOtherDatagrams = 500;  ///< at 1 % loss, none lost one time in 150

sockaddr_in at(const char* address, std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  ::inet_pton(AF_INET, address, &a.sin_addr);
  return a;
}

bool isTcp(const std::vector<std::uint8_t>& ip) { return ip.size() >= 20 && (ip[0] >> 4) == 4 && ip[9] == IPPROTO_TCP; }

/// An IPv4 TCP segment to port with a payload (not a bare SYN or ACK).
bool isDataSegmentTo(const std::vector<std::uint8_t>& ip, std::uint16_t port) {
  if (!isTcp(ip)) return false;
  const std::size_t ip_header = std::size_t(ip[0] & 0x0f) * 4, total = std::size_t(ip[2]) << 8 | ip[3];
  if (ip.size() < ip_header + 20 || total > ip.size()) return false;
  const std::uint8_t* tcp = ip.data() + ip_header;
  const std::size_t tcp_header = std::size_t(tcp[12] >> 4) * 4;
  return (std::uint16_t(tcp[2]) << 8 | tcp[3]) == port && total > ip_header + tcp_header;
}

/// Packets the device's own queue dropped on the way out (the relay read too late), from this
/// thread's namespace; 0 when the device is not there.
std::uint64_t txDropped(const char* device) {
  std::FILE* file = std::fopen("/proc/thread-self/net/dev", "r");
  if (!file) return 0;
  char line[512];
  std::uint64_t dropped = 0;
  const std::string prefix = std::string(device) + ":";
  while (std::fgets(line, sizeof line, file)) {
    const char* name = line + std::strspn(line, " ");
    if (std::strncmp(name, prefix.c_str(), prefix.size()) != 0) continue;
    unsigned long long f[12] = {};  // rx: bytes packets errs drop fifo frame compressed multicast; tx: bytes packets errs drop
    if (std::sscanf(name + prefix.size(), "%llu %llu %llu %llu %llu %llu %llu %llu %llu %llu %llu %llu", &f[0], &f[1], &f[2],
                    &f[3], &f[4], &f[5], &f[6], &f[7], &f[8], &f[9], &f[10], &f[11]) == 12)
      dropped = f[11];
  }
  std::fclose(file);
  return dropped;
}

std::uint8_t patternByte(std::size_t i) { return static_cast<std::uint8_t>((i * 2654435761u) >> 13); }

TEST(TunRelay, KernelTcpCrossesTheImpairedPathWithItsRetransmissionsAndPinnedCongestionControl) {
  std::string error, skip_reason;
  bool done = false;
  // A thread of its own: the private namespace is the thread's (and what it starts).
  std::thread([&] {
    if (!enterPrivateNetworkNamespace(&error)) {
      if (::geteuid() == 0) ADD_FAILURE() << "as root: " << error;
      else skip_reason = error;  // no privilege: the only case that skips
      return;
    }
    TunRelayOptions options;
    for (PathOptions* p : {&options.to_far, &options.to_near}) p->one_way_delay_ns = 20 * kMs;
    options.to_far.loss.loss_fraction = 0.01;
    options.to_far.loss.seed = 11;
    options.to_far.rate = RateTrace::constant(20e6);
    options.to_far.queue_limit_bytes = 256 << 10;
    std::atomic<std::uint64_t> seen_to_far = 0, stream_data_to_far = 0, other_to_far = 0;  // the relay's thread counts
    options.on_arrival = [&](const PathPacket& packet, bool to_far) {
      if (!to_far) return;
      ++seen_to_far;
      if (isDataSegmentTo(packet.bytes, kPort)) ++stream_data_to_far;
      else if (!isTcp(packet.bytes)) ++other_to_far;
    };
    auto relay = TunRelay::start(options, &error);
    ASSERT_TRUE(relay) << error;

    // The server listens in the far namespace (a socket stays in the namespace it was made in).
    int listener = -1;
    ASSERT_TRUE(runInNetworkNamespace(relay->farNamespace(), [&] {
      listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
      const sockaddr_in address = at(TunRelay::kFarAddress, kPort);
      const int one = 1;
      ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
      if (::bind(listener, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 || ::listen(listener, 1) != 0) {
        ::close(listener);
        listener = -1;
      }
    }, &error)) << error;
    ASSERT_GE(listener, 0) << std::strerror(errno);

    const int client = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const sockaddr_in server = at(TunRelay::kFarAddress, kPort);
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(::connect(client, reinterpret_cast<const sockaddr*>(&server), sizeof server), 0) << std::strerror(errno);
    const double handshake_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_GE(handshake_ms, 40.0) << "SYN and SYN-ACK each cross one way";
    char congestion[16] = {};
    socklen_t length = sizeof congestion;
    ASSERT_EQ(::getsockopt(client, IPPROTO_TCP, TCP_CONGESTION, congestion, &length), 0);
    EXPECT_STREQ(congestion, "cubic") << "the route pins it";
    const int accepted = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
    ASSERT_GE(accepted, 0);

    // Other traffic shares the path, as the media's UDP does beside a TCP link: its losses are
    // nobody's to resend, so they must not count against the stream's.
    {
      const int udp = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
      ASSERT_GE(udp, 0);
      const sockaddr_in discard = at(TunRelay::kFarAddress, kPort + 1);
      const std::vector<std::uint8_t> datagram(64, 0x5a);
      for (int i = 0; i < kOtherDatagrams; ++i)
        ::sendto(udp, datagram.data(), datagram.size(), 0, reinterpret_cast<const sockaddr*>(&discard), sizeof discard);
      ::close(udp);
    }

    // 2 MB near → far, checked byte by byte as they arrive.
    constexpr std::size_t kBytes = 2'000'000;
    std::size_t received = 0, mismatches = 0;
    std::thread reader([&] {
      std::vector<std::uint8_t> buffer(65536);
      pollfd fd{accepted, POLLIN, 0};
      while (received < kBytes && ::poll(&fd, 1, 20'000) > 0) {
        const ssize_t n = ::recv(accepted, buffer.data(), buffer.size(), 0);
        if (n <= 0) break;
        for (ssize_t i = 0; i < n; ++i) mismatches += buffer[std::size_t(i)] != patternByte(received + std::size_t(i));
        received += std::size_t(n);
      }
    });
    std::vector<std::uint8_t> data(kBytes);
    for (std::size_t i = 0; i < kBytes; ++i) data[i] = patternByte(i);
    const timeval send_timeout{30, 0};
    ::setsockopt(client, SOL_SOCKET, SO_SNDTIMEO, &send_timeout, sizeof send_timeout);
    const auto t_send = std::chrono::steady_clock::now();
    for (std::size_t sent = 0; sent < kBytes;) {
      const ssize_t n = ::send(client, data.data() + sent, kBytes - sent, MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += std::size_t(n);
    }
    reader.join();
    const double transfer_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_send).count();
    EXPECT_EQ(received, kBytes);
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GE(transfer_s, 8.0 * kBytes / 20e6) << "no faster than the 20 Mbit/s bottleneck";
    tcp_info info{};
    length = sizeof info;
    ASSERT_EQ(::getsockopt(client, IPPROTO_TCP, TCP_INFO, &info, &length), 0);
    ASSERT_GE(length, offsetof(tcp_info, tcpi_data_segs_out) + sizeof info.tcpi_data_segs_out);
    // What was sent by now has left the path (or been lost) after the one-way delay; the queue
    // holds no more than the spurious retransmissions of the last round trip.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const TunRelayStats stats = relay->stats();
    const std::uint64_t device_dropped = txDropped("ts-near");
    const std::uint64_t stream_data_lost =
        info.tcpi_data_segs_out > stream_data_to_far ? info.tcpi_data_segs_out - stream_data_to_far : 0;
    std::printf("2 MB through 40 ms RTT, 1 %% loss, 20 Mbit/s: %.2f s (%.1f Mbit/s), handshake %.1f ms, "
                "%u data segments sent, %llu of them lost, %u retransmitted by TCP; the relay lost %llu "
                "packets in all and carried %llu that were not TCP; the device's queue dropped %llu; srtt %.1f ms\n",
                transfer_s, 8.0 * kBytes / transfer_s * 1e-6, handshake_ms, info.tcpi_data_segs_out,
                static_cast<unsigned long long>(stream_data_lost), info.tcpi_total_retrans,
                static_cast<unsigned long long>(stats.to_far.lost), static_cast<unsigned long long>(other_to_far.load()),
                static_cast<unsigned long long>(device_dropped), info.tcpi_rtt / 1000.0);
    EXPECT_GT(stream_data_lost, 0u) << "1 % of ~1400 segments";
    EXPECT_LE(stream_data_lost, stats.to_far.lost + stats.to_far.dropped_queue + device_dropped)
        << "lost only by the relay, its queue, or the device's queue before it";
    EXPECT_GE(info.tcpi_total_retrans, stream_data_lost) << "each lost data segment was sent again";
    EXPECT_GE(other_to_far, std::uint64_t(kOtherDatagrams * 9 / 10)) << "the other traffic crossed too";
    EXPECT_GE(info.tcpi_rtt / 1000.0, 40.0);
    EXPECT_EQ(stats.write_errors, 0u);
    EXPECT_EQ(seen_to_far, stats.to_far.delivered);
    ::close(client);
    ::close(accepted);
    ::close(listener);
    done = true;
  }).join();
  if (!skip_reason.empty()) GTEST_SKIP() << "needs CAP_NET_ADMIN (root): " << skip_reason;
  EXPECT_TRUE(done) << "the transfer did not run to its end (see the failures above)";
}

}  // namespace
}  // namespace telesphere::bench::impairment
