// SPDX-License-Identifier: MIT
/// @brief Hostile bytes on every port of a keyed link (DESIGN.md §10), over real sockets: while
///        an authenticated operator takes frames and a supervisor pings, peers without a key send
///        random bytes, truncated and oversized ZeroMQ greetings, hold connections open a byte at
///        a time (slow loris) and open and close connections as fast as they can (a flood). The
///        operator's frames keep arriving, the supervisor keeps its answers, and the robot counts
///        the attempts it could see.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <random>
#include <thread>
#include <vector>

#include "robot/link/link_client.h"
#include "robot/link/link_server.h"
#include "robot/link/trust/link_key_files.h"
#include "tests/robot/link/loopback_tcp.h"

namespace telesphere::link {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using trust::LinkRole;

constexpr int kPort = 28620;

struct HostileKeys {
  fs::path root = fs::temp_directory_path() / ("telesphere-hostile-" + std::to_string(::getpid()));
  LinkEndpoints server, operator_, supervisor;

  HostileKeys() {
    fs::remove_all(root);
    std::string error;
    const auto robot = trust::generateKeyPair("robot", LinkRole::kRobot, &error);
    EXPECT_TRUE(trust::writeKeyPair(*robot, root / "robot", false, &error)) << error;
    fs::create_directories(root / "robot" / "allowed");
    for (const auto& [name, role] : {std::pair{"olga", LinkRole::kOperator}, std::pair{"sam", LinkRole::kSupervisor}}) {
      const auto pair = trust::generateKeyPair(name, role, &error);
      EXPECT_TRUE(trust::writeKeyPair(*pair, root / name, false, &error)) << error;
      fs::copy_file(root / name / (std::string(name) + ".pub"), root / "robot" / "allowed" / (std::string(name) + ".pub"));
      fs::copy_file(root / "robot" / "robot.pub", root / name / "robot.pub");
    }
    server.base_port = operator_.base_port = supervisor.base_port = kPort;
    server.credentials = *trust::loadRobotCredentials(root / "robot", &error);
    operator_.credentials = *trust::loadClientCredentials(root / "olga", {LinkRole::kOperator}, &error);
    supervisor.credentials = *trust::loadClientCredentials(root / "sam", {LinkRole::kSupervisor}, &error);
  }
  ~HostileKeys() { fs::remove_all(root); }
};

void writeAll(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n <= 0) return;  // the robot closed it: fine
    done += std::size_t(n);
  }
}

/// A ZMTP 3.0 greeting (signature, version 3.0, mechanism) that a real libzmq peer would send.
std::vector<std::uint8_t> greeting(const char* mechanism) {
  std::vector<std::uint8_t> g{0xFF, 0, 0, 0, 0, 0, 0, 0, 1, 0x7F, 3, 0};
  std::vector<std::uint8_t> m(20, 0);
  std::copy(mechanism, mechanism + std::strlen(mechanism), m.begin());
  g.insert(g.end(), m.begin(), m.end());
  g.push_back(0);  // as-server
  g.insert(g.end(), 31, 0);
  return g;
}

TEST(LinkHostile, EveryPortSurvivesHostilePeersAndKeepsServingTheAuthenticatedOnes) {
  HostileKeys keys;
  LinkServer server(keys.server);
  server.setControlHandler([](const proto::ControlRequest&) {
    proto::ControlReply reply;
    reply.set_ok(true);
    return reply;
  });
  LinkClient olga(keys.operator_, {.frames = true});
  LinkClient sam(keys.supervisor, {.frames = false});

  std::atomic<bool> running{true};
  std::atomic<std::uint64_t> published{0};
  std::thread publisher([&] {
    const auto jpeg = std::make_shared<const std::vector<std::uint8_t>>(std::vector<std::uint8_t>(20000, 0x55));
    while (running) {
      proto::StereoFrame frame;
      frame.set_sequence(++published);
      for (auto* image : {frame.mutable_left(), frame.mutable_right()}) {
        image->set_width(64);
        image->set_height(64);
      }
      server.publishStereoFrame(frame, jpeg, jpeg);
      std::this_thread::sleep_for(20ms);  // 50 Hz
    }
  });
  ASSERT_TRUE(olga.waitForFrame(5000ms)) << "no frame before the attack";

  std::vector<std::thread> attackers;
  std::atomic<std::uint64_t> connections{0};
  const auto attack_until = std::chrono::steady_clock::now() + 7s;
  const auto attacking = [&] { return std::chrono::steady_clock::now() < attack_until; };
  for (int k = 0; k < 4; ++k) {
    const int port = kPort + k;
    // Random bytes, random lengths.
    attackers.emplace_back([&, port, k] {
      std::mt19937 rng(1000 + k);
      while (attacking()) {
        const int fd = test::connectLoopbackTcp(port);
        if (fd < 0) continue;
        ++connections;
        std::vector<std::uint8_t> junk(1 + rng() % 70000);
        for (auto& b : junk) b = std::uint8_t(rng());
        writeAll(fd, junk);
        ::close(fd);
      }
    });
    // Greetings: truncated, without a key (NULL), CURVE followed by garbage, PLAIN, and a frame
    // header claiming 2^62 bytes.
    attackers.emplace_back([&, port, k] {
      std::mt19937 rng(2000 + k);
      int round = 0;
      while (attacking()) {
        const int fd = test::connectLoopbackTcp(port);
        if (fd < 0) continue;
        ++connections;
        std::vector<std::uint8_t> g = greeting(round % 4 == 0 ? "NULL" : round % 4 == 1 ? "CURVE" : "PLAIN");
        switch (round++ % 5) {
          case 0: g.resize(1 + rng() % g.size()); break;           // truncated
          case 1: for (int i = 0; i < 200; ++i) g.push_back(std::uint8_t(rng())); break;
          case 2: g.insert(g.end(), {0x02, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}); break;  // long frame
          default: break;
        }
        writeAll(fd, g);
        std::this_thread::sleep_for(2ms);
        ::close(fd);
      }
    });
  }
  // Slow loris: 40 connections that send one byte every 300 ms.
  attackers.emplace_back([&] {
    std::vector<int> fds;
    for (int i = 0; i < 40; ++i) {
      const int fd = test::connectLoopbackTcp(kPort + i % 4);
      if (fd >= 0) fds.push_back(fd);
    }
    connections += fds.size();
    const std::uint8_t byte = 0xFF;
    while (attacking()) {
      for (int fd : fds) ::send(fd, &byte, 1, MSG_NOSIGNAL | MSG_DONTWAIT);
      std::this_thread::sleep_for(300ms);
    }
    for (int fd : fds) ::close(fd);
  });
  // A flood: connect and close at once.
  attackers.emplace_back([&] {
    while (attacking()) {
      for (int k = 0; k < 4; ++k) {
        const int fd = test::connectLoopbackTcp(kPort + k);
        if (fd >= 0) {
          ++connections;
          ::close(fd);
        }
      }
    }
  });

  // Meanwhile: the operator's frames, the supervisor's requests.
  std::uint64_t frames = 0, last_sequence = 0, replies = 0, requests = 0;
  std::int64_t largest_gap_ms = 0;
  auto last_frame = std::chrono::steady_clock::now();
  const std::uint64_t published_before = published;
  auto next_request = std::chrono::steady_clock::now();
  while (attacking()) {
    if (auto f = olga.waitForFrame(50ms)) {
      ++frames;
      EXPECT_GT(f->frame.sequence(), last_sequence);
      last_sequence = f->frame.sequence();
      const auto now = std::chrono::steady_clock::now();
      largest_gap_ms = std::max<std::int64_t>(
          largest_gap_ms, std::chrono::duration_cast<std::chrono::milliseconds>(now - last_frame).count());
      last_frame = now;
    }
    if (std::chrono::steady_clock::now() >= next_request) {
      proto::ControlRequest r;
      r.set_get_settings(true);
      ++requests;
      if (const auto reply = sam.request(r, 1000ms); reply && reply->ok()) ++replies;
      next_request = std::chrono::steady_clock::now() + 500ms;
    }
  }
  for (auto& t : attackers) t.join();
  const std::uint64_t published_during = published - published_before;
  running = false;
  publisher.join();

  std::cout << "hostile peers: " << connections << " connections; operator: " << frames << " of " << published_during
            << " frames, largest gap " << largest_gap_ms << " ms; supervisor: " << replies << " of " << requests
            << " replies; robot counted " << server.trustHealth().refused_total() << " refusals\n";
  EXPECT_GT(connections, 1000u);
  // Latest wins: the operator may skip frames while its loop asks the supervisor's questions;
  // what must not happen is a stall.
  EXPECT_GE(double(frames), 0.5 * double(published_during)) << "the operator's frames stalled under attack";
  EXPECT_LT(largest_gap_ms, 1000);
  EXPECT_EQ(replies, requests);
  EXPECT_GT(server.trustHealth().refused_total(), 0u);
  // And after it: a new authenticated client is heard at once.
  LinkClient later(keys.supervisor, {.frames = false});
  proto::ControlRequest r;
  r.set_get_settings(true);
  const auto reply = later.request(r, 3000ms);
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok());
}

}  // namespace
}  // namespace telesphere::link
