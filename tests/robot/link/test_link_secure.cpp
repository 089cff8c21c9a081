// SPDX-License-Identifier: MIT
/// @brief The link with keys (DESIGN.md §10) on real sockets: a real LinkServer and LinkClients
///        with CURVE keys made by libzmq, on loopback. Who gets in and who is refused (no key, an
///        unknown key, a viewer that tries to stop the arm, a second operator), each refusal
///        counted by cause and address and answered where the socket allows; keys revoked and
///        added while running, with a peer whose key stayed never interrupted; and a relay on the
///        wire that finds no JPEG marker and no text of the messages it carried.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
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

/// A folder of keys like the demo's: the robot's pair and allowed/, one folder per client.
struct KeyRing {
  fs::path root;
  trust::LinkKeyPair robot;

  explicit KeyRing(const std::string& suffix = "")
      : root(fs::temp_directory_path() / ("telesphere-secure-" + std::to_string(::getpid()) + "-" +
                                          ::testing::UnitTest::GetInstance()->current_test_info()->name() + suffix)) {
    fs::remove_all(root);
    robot = make("robot", LinkRole::kRobot);
    fs::create_directories(root / "robot" / "allowed");
  }
  ~KeyRing() { fs::remove_all(root); }

  trust::LinkKeyPair make(const std::string& name, LinkRole role) {
    std::string error;
    auto pair = trust::generateKeyPair(name, role, &error);
    EXPECT_TRUE(pair) << error;
    EXPECT_TRUE(trust::writeKeyPair(*pair, root / name, false, &error)) << error;
    return *pair;
  }
  /// A client `name` in `role`, trusted by the robot when `allowed`.
  LinkEndpoints client(int port, const std::string& name, LinkRole role, bool allowed = true) {
    const auto pair = make(name, role);
    if (allowed) allow(name);
    std::string error;
    fs::copy_file(root / "robot" / "robot.pub", root / name / "robot.pub", fs::copy_options::overwrite_existing);
    auto credentials = trust::loadClientCredentials(root / name, {role}, &error);
    EXPECT_TRUE(credentials) << error;
    LinkEndpoints e;
    e.base_port = port;
    e.credentials = *credentials;
    return e;
  }
  void allow(const std::string& name) {
    fs::copy_file(root / name / (name + ".pub"), root / "robot" / "allowed" / (name + ".pub"),
                  fs::copy_options::overwrite_existing);
  }
  void revoke(const std::string& name) { fs::remove(root / "robot" / "allowed" / (name + ".pub")); }
  LinkEndpoints server(int port) const {
    std::string error;
    auto credentials = trust::loadRobotCredentials(root / "robot", &error);
    EXPECT_TRUE(credentials) << error;
    LinkEndpoints e;
    e.base_port = port;
    e.credentials = *credentials;
    return e;
  }
};

bool waitUntil(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return condition();
}

bool hearsRobot(const LinkClient& client, std::chrono::milliseconds timeout = 3000ms) {
  return waitUntil([&] { return client.activity().robot_pong_ns != 0; }, timeout);
}

/// The refusals counted for `cause`, summed over peers.
std::uint64_t refusedFor(const LinkServer& server, const std::string& cause) {
  std::uint64_t n = 0;
  const proto::LinkTrustHealth health = server.trustHealth();
  for (const auto& r : health.refusals())
    if (r.cause() == cause) n += r.count();
  return n;
}

std::optional<proto::LinkRefusal> refusal(const proto::LinkTrustHealth& health, const std::string& cause) {
  for (const auto& r : health.refusals())
    if (r.cause() == cause) return r;
  return std::nullopt;
}

proto::HeadTarget headTarget(double x, std::int64_t t_ns) {
  proto::HeadTarget t;
  t.set_t_ns(t_ns);
  t.set_valid(true);
  t.mutable_t_vr_hmd()->set_tx(x);
  t.mutable_t_vr_hmd()->set_qw(1.0);
  return t;
}

TEST(LinkSecure, AnAllowedSupervisorIsHeardAndItsRequestsRun) {
  KeyRing keys;
  const LinkEndpoints supervisor = keys.client(28500, "alice", LinkRole::kSupervisor);
  LinkServer server(keys.server(28500));
  std::atomic<int> handled{0};
  server.setControlHandler([&](const proto::ControlRequest&) {
    ++handled;
    proto::ControlReply reply;
    reply.set_ok(true);
    return reply;
  });
  LinkClient client(supervisor, {.frames = true});
  ASSERT_TRUE(hearsRobot(client));
  proto::ControlRequest stop;
  stop.set_arm_stop(true);
  const auto reply = client.request(stop, 2000ms);
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok()) << reply->error();
  EXPECT_EQ(handled, 1);
  const auto health = server.trustHealth();
  EXPECT_FALSE(health.insecure());
  ASSERT_EQ(health.allowed_size(), 1);
  EXPECT_EQ(health.allowed(0), "alice (supervisor)");
  EXPECT_EQ(health.refused_total(), 0u);
}

TEST(LinkSecure, APeerWithoutAKeyIsRefusedAndCounted) {
  KeyRing keys;
  LinkServer server(keys.server(28510));
  LinkEndpoints plain;
  plain.base_port = 28510;  // no credentials: plain ZeroMQ
  LinkClient client(plain, {.frames = false});
  EXPECT_FALSE(hearsRobot(client, 1500ms));
  // Which end sees the mismatch first is a race: the robot counts "no key" when it read the
  // peer's greeting, "broken handshake" when the peer hung up before sending its mechanism.
  EXPECT_TRUE(waitUntil([&] { return refusedFor(server, "no key") + refusedFor(server, "broken handshake") > 0; }, 3000ms))
      << server.trustHealth().DebugString();
  if (const auto r = refusal(server.trustHealth(), "no key")) {
    EXPECT_NE(r->detail().find("did not use CURVE"), std::string::npos) << r->detail();
  }
  // The reason stays the mismatch once it was heard, though later attempts may only see the
  // robot hang up (EPIPE): a program may stop waiting on it. The client may have seen only hang-ups
  // so far (a loaded CI machine: the robot logged the control channel's mismatch 1.3 s in, and
  // the client's reconnect came after this test looked): it settles on a later attempt.
  EXPECT_TRUE(waitUntil([&] { return client.activity().refusal_settled; }, 5000ms))
      << client.activity().refused_reason;
  EXPECT_NE(client.activity().refused_reason.find("--insecure"), std::string::npos)
      << client.activity().refused_reason;
  EXPECT_TRUE(client.activity().refusal_settled);
}

TEST(LinkSecure, AnUnknownKeyIsRefusedWithItsAddressAndTheClientIsTold) {
  KeyRing keys;
  const LinkEndpoints stranger = keys.client(28520, "mallory", LinkRole::kSupervisor, /*allowed=*/false);
  LinkServer server(keys.server(28520));
  std::atomic<int> handled{0};
  server.setControlHandler([&](const proto::ControlRequest&) {
    ++handled;
    return proto::ControlReply();
  });
  LinkClient client(stranger, {.frames = true});
  proto::ControlRequest stop;
  stop.set_arm_stop(true);
  EXPECT_FALSE(client.request(stop, 1500ms));
  EXPECT_EQ(client.activity().robot_pong_ns, 0);
  EXPECT_EQ(handled, 0);
  ASSERT_TRUE(waitUntil([&] { return refusedFor(server, "unknown key") > 0; }, 3000ms));
  const auto r = refusal(server.trustHealth(), "unknown key");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->peer(), "127.0.0.1");
  EXPECT_NE(client.activity().refused_reason.find("allowed/"), std::string::npos)
      << client.activity().refused_reason;
  EXPECT_TRUE(client.activity().refusal_settled);
}

TEST(LinkSecure, AClientHoldingAnotherRobotsKeyIsRefused) {
  KeyRing keys;
  KeyRing other("-other");  // another robot: the client trusts its key, not ours
  LinkEndpoints client_endpoints = keys.client(28530, "alice", LinkRole::kSupervisor);
  client_endpoints.credentials.robot_public_z85 = other.robot.key.public_z85;
  LinkServer server(keys.server(28530));
  LinkClient client(client_endpoints, {.frames = false});
  EXPECT_FALSE(hearsRobot(client, 1500ms));
  EXPECT_TRUE(waitUntil([&] { return refusedFor(server, "wrong robot key") > 0; }, 3000ms))
      << server.trustHealth().DebugString();
}

TEST(LinkSecure, AViewerCannotStopTheArmNorWatchTheFullFrames) {
  KeyRing keys;
  const LinkEndpoints viewer = keys.client(28540, "victor", LinkRole::kViewer);
  LinkServer server(keys.server(28540));
  std::atomic<int> handled{0};
  server.setControlHandler([&](const proto::ControlRequest&) {
    ++handled;
    return proto::ControlReply();
  });
  LinkClient client(viewer, {.frames = true});
  ASSERT_TRUE(hearsRobot(client));  // pings are anyone's: the clock offset
  proto::ControlRequest stop;
  stop.set_arm_stop(true);
  const auto reply = client.request(stop, 2000ms);
  ASSERT_TRUE(reply);
  EXPECT_FALSE(reply->ok());
  EXPECT_NE(reply->error().find("arm_stop"), std::string::npos) << reply->error();
  EXPECT_NE(reply->error().find("supervisor"), std::string::npos) << reply->error();
  EXPECT_EQ(handled, 0);
  // Telemetry reaches a viewer; the full-rate frames channel refused it at the handshake.
  proto::RobotState state;
  state.set_arm_ok(true);
  ASSERT_TRUE(waitUntil(
      [&] {
        server.publishRobotState(state);
        auto frame = std::make_shared<const std::vector<std::uint8_t>>(std::vector<std::uint8_t>{0xFF, 0xD8, 0xFF});
        proto::StereoFrame stereo;
        for (auto* image : {stereo.mutable_left(), stereo.mutable_right()}) {
          image->set_width(16);
          image->set_height(16);
        }
        server.publishStereoFrame(stereo, frame, frame);
        return client.latestRobotState().has_value();
      },
      3000ms));
  EXPECT_FALSE(client.waitForFrame(500ms));
  const auto health = server.trustHealth();
  const auto role = refusal(health, "role");
  ASSERT_TRUE(role);
  EXPECT_EQ(role->name(), "victor");
  EXPECT_GE(refusedFor(server, "role"), 2u);  // the stop and the frames channel
}

TEST(LinkSecure, OneOperatorSeatUntilASupervisorHandsItOver) {
  KeyRing keys;
  const LinkEndpoints first = keys.client(28550, "olga", LinkRole::kOperator);
  const LinkEndpoints second = keys.client(28550, "oscar", LinkRole::kOperator);
  const LinkEndpoints supervisor = keys.client(28550, "sam", LinkRole::kSupervisor);
  LinkServer server(keys.server(28550));
  LinkClient olga(first, {.frames = true}), oscar(second, {.frames = true}), sam(supervisor, {.frames = false});
  ASSERT_TRUE(hearsRobot(olga));
  ASSERT_TRUE(hearsRobot(oscar));
  ASSERT_TRUE(hearsRobot(sam));
  ASSERT_TRUE(waitUntil(
      [&] {
        olga.sendHeadTarget(headTarget(0.1, linkNowNs()));
        return server.latestHeadTarget().has_value();
      },
      3000ms));
  EXPECT_EQ(server.trustHealth().operator_seat(), "olga");
  // Oscar's targets never become the latest; each is refused with Olga's name.
  for (int i = 0; i < 20; ++i) {
    oscar.sendHeadTarget(headTarget(0.9, linkNowNs()));
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_TRUE(waitUntil([&] { return refusedFor(server, "operator seat") > 0; }, 3000ms));
  EXPECT_DOUBLE_EQ(server.latestHeadTarget()->t_vr_hmd().tx(), 0.1);
  const auto seat = refusal(server.trustHealth(), "operator seat");
  ASSERT_TRUE(seat);
  EXPECT_EQ(seat->name(), "oscar");
  EXPECT_NE(seat->detail().find("held by olga"), std::string::npos) << seat->detail();

  // An operator may not hand the seat over; the supervisor may.
  proto::ControlRequest hand;
  hand.mutable_hand_over_operator_seat()->set_name("oscar");
  const auto by_olga = olga.request(hand, 2000ms);
  ASSERT_TRUE(by_olga);
  EXPECT_FALSE(by_olga->ok());
  const auto by_sam = sam.request(hand, 2000ms);
  ASSERT_TRUE(by_sam);
  EXPECT_TRUE(by_sam->ok()) << by_sam->error();
  EXPECT_EQ(server.trustHealth().operator_seat(), "oscar");
  ASSERT_TRUE(waitUntil(
      [&] {
        oscar.sendHeadTarget(headTarget(0.9, linkNowNs()));
        return server.latestHeadTarget()->t_vr_hmd().tx() == 0.9;
      },
      3000ms));
}

TEST(LinkSecure, RevokedKeysAreRefusedNewKeysAdmittedAndStayingPeersUninterrupted) {
  KeyRing keys;
  const LinkEndpoints staying = keys.client(28560, "sam", LinkRole::kSupervisor);
  const LinkEndpoints revoked = keys.client(28560, "rita", LinkRole::kSupervisor);
  const LinkEndpoints added = keys.client(28560, "nina", LinkRole::kSupervisor, /*allowed=*/false);
  const LinkEndpoints connected = keys.client(28560, "rex", LinkRole::kSupervisor);
  LinkServer server(keys.server(28560));
  server.setControlHandler([](const proto::ControlRequest&) {
    proto::ControlReply reply;
    reply.set_ok(true);
    return reply;
  });
  LinkClient sam(staying, {.frames = false});
  ASSERT_TRUE(hearsRobot(sam));
  LinkClient rex(connected, {.frames = false});  // stays connected while its key is revoked
  ASSERT_TRUE(hearsRobot(rex));
  {
    LinkClient rita(revoked, {.frames = false});
    ASSERT_TRUE(hearsRobot(rita));
  }
  // The staying peer hears every state message published from here on.
  std::atomic<bool> publishing{true};
  std::atomic<std::int64_t> published{0};
  std::thread publisher([&] {
    proto::RobotState state;
    while (publishing) {
      state.set_t_ns(++published);
      server.publishRobotState(state);
      std::this_thread::sleep_for(5ms);
    }
  });
  keys.revoke("rita");
  keys.revoke("rex");
  keys.allow("nina");
  const auto reloads = server.trustHealth().allowed_reloads();
  std::int64_t largest_gap_ms = 0, last_seen = 0;
  auto last_change = std::chrono::steady_clock::now();
  const auto watch = [&] {
    const auto s = sam.latestRobotState();
    const auto now = std::chrono::steady_clock::now();
    if (s && s->t_ns() != last_seen) {
      largest_gap_ms = std::max<std::int64_t>(
          largest_gap_ms, std::chrono::duration_cast<std::chrono::milliseconds>(now - last_change).count());
      last_seen = s->t_ns();
      last_change = now;
    }
  };
  // allowed/ is read again within a second of a change.
  LinkClient nina(added, {.frames = false});
  const bool nina_heard = waitUntil(
      [&] {
        watch();
        return nina.activity().robot_pong_ns != 0;
      },
      5000ms);
  if (!nina_heard) {
    publishing = false;
    publisher.join();
    const auto h = server.trustHealth();
    FAIL() << "the added key was not let in: " << h.DebugString() << " client: " << nina.activity().refused_reason
           << " (" << nina.activity().handshakes_refused << " refused)";
  }
  EXPECT_GT(server.trustHealth().allowed_reloads(), reloads);
  LinkClient rita_again(revoked, {.frames = false});
  const auto until = std::chrono::steady_clock::now() + 1500ms;
  while (std::chrono::steady_clock::now() < until) {
    watch();
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_EQ(rita_again.activity().robot_pong_ns, 0);
  EXPECT_GT(refusedFor(server, "unknown key"), 0u);
  // A revoked key on a connection let in before: refused from its next request on.
  proto::ControlRequest settings;
  settings.set_get_settings(true);
  const auto rex_reply = rex.request(settings, 2000ms);
  ASSERT_TRUE(rex_reply);
  EXPECT_FALSE(rex_reply->ok());
  EXPECT_NE(rex_reply->error().find("no longer allowed"), std::string::npos) << rex_reply->error();
  EXPECT_GT(refusedFor(server, "revoked key"), 0u);
  const auto sam_reply = sam.request(settings, 2000ms);
  ASSERT_TRUE(sam_reply);
  EXPECT_TRUE(sam_reply->ok());
  publishing = false;
  publisher.join();
  EXPECT_LT(largest_gap_ms, 250) << "the staying supervisor's state stream stood still";
  EXPECT_GT(last_seen, 0);
}

/// A TCP relay between a client and the server's four ports that keeps every byte it carried.
class WireTap {
 public:
  WireTap(int listen_base, int server_base) {
    for (int k = 0; k < 4; ++k) threads_.emplace_back([this, listen_base, server_base, k] { relay(listen_base + k, server_base + k); });
  }
  ~WireTap() {
    running_ = false;
    for (auto& t : threads_) t.join();
  }
  std::string bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
  }

 private:
  static int listenOn(int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0) << "port " << port;
    ::listen(fd, 8);
    return fd;
  }
  void relay(int listen_port, int server_port) {
    const int listener = listenOn(listen_port);
    std::vector<std::pair<int, int>> pairs;  // client, server
    while (running_) {
      std::vector<pollfd> fds{{listener, POLLIN, 0}};
      for (auto [c, s] : pairs) {
        fds.push_back({c, POLLIN, 0});
        fds.push_back({s, POLLIN, 0});
      }
      if (::poll(fds.data(), fds.size(), 20) <= 0) continue;
      if (fds[0].revents & POLLIN) {
        const int c = ::accept(listener, nullptr, nullptr);
        const int s = test::connectLoopbackTcp(server_port);
        if (s < 0) ::close(c);
        else pairs.emplace_back(c, s);
      }
      for (std::size_t i = 1; i < fds.size(); ++i) {
        if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
        auto& [c, s] = pairs[(i - 1) / 2];
        const int from = fds[i].fd, to = from == c ? s : c;
        char buffer[65536];
        const ssize_t n = ::read(from, buffer, sizeof buffer);
        if (n <= 0) {
          ::shutdown(to, SHUT_WR);
          continue;
        }
        {
          std::lock_guard lock(mutex_);
          bytes_.append(buffer, std::size_t(n));
        }
        for (ssize_t done = 0; done < n;) {
          const ssize_t w = ::write(to, buffer + done, std::size_t(n - done));
          if (w <= 0) break;
          done += w;
        }
      }
    }
    for (auto [c, s] : pairs) {
      ::close(c);
      ::close(s);
    }
    ::close(listener);
  }

  std::atomic<bool> running_{true};
  mutable std::mutex mutex_;
  std::string bytes_;
  std::vector<std::thread> threads_;
};

/// Runs a session through a wire tap (frames with a JPEG, state, a control request carrying text,
/// head targets) and returns what the wire carried.
std::string wireOfASession(LinkEndpoints server_endpoints, LinkEndpoints client_endpoints, int tap_base) {
  LinkServer server(server_endpoints);
  std::string calibration_text;
  server.setControlHandler([&](const proto::ControlRequest& r) {
    proto::ControlReply reply;
    reply.set_ok(true);
    if (r.has_apply_calibration()) calibration_text = r.apply_calibration().text();
    return reply;
  });
  WireTap tap(tap_base, server_endpoints.base_port);
  client_endpoints.base_port = tap_base;
  LinkClient client(client_endpoints, {.frames = true});
  EXPECT_TRUE(hearsRobot(client));
  // A JPEG's start of image, APP0 and the JFIF text, as the robot's encoder writes them.
  const std::vector<std::uint8_t> jpeg{0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x10, 'J', 'F', 'I', 'F', 0x00, 0xFF, 0xD9};
  auto image = std::make_shared<const std::vector<std::uint8_t>>(jpeg);
  proto::RobotState state;
  state.set_fault("SECRET-FAULT-TEXT");
  EXPECT_TRUE(waitUntil(
      [&] {
        proto::StereoFrame frame;
        for (auto* image : {frame.mutable_left(), frame.mutable_right()}) {
          image->set_width(16);
          image->set_height(16);
        }
        server.publishStereoFrame(frame, image, image);
        server.publishRobotState(state);
        return client.waitForFrame(50ms).has_value() && client.latestRobotState().has_value();
      },
      3000ms));
  proto::ControlRequest apply;
  apply.mutable_apply_calibration()->set_text("cam0:\n  camera_model: ds\n  intrinsics: [1, 2, 3, 4, 5, 6]\n");
  EXPECT_TRUE(client.request(apply, 2000ms));
  EXPECT_NE(calibration_text.find("camera_model"), std::string::npos);
  return tap.bytes();
}

bool carriesPlaintext(const std::string& wire) {
  return wire.find("\xFF\xD8\xFF") != std::string::npos || wire.find("JFIF") != std::string::npos ||
         wire.find("SECRET-FAULT-TEXT") != std::string::npos ||
         wire.find("camera_model") != std::string::npos;
}

TEST(LinkSecure, TheWireCarriesNoJpegNoMessageTextNoCalibration) {
  KeyRing keys;
  const LinkEndpoints supervisor = keys.client(28570, "alice", LinkRole::kSupervisor);
  const std::string wire = wireOfASession(keys.server(28570), supervisor, 28580);
  EXPECT_GT(wire.size(), 1000u);
  EXPECT_FALSE(carriesPlaintext(wire));
  // The check can fail: the same session without keys shows all of it on the wire.
  LinkEndpoints plain_server, plain_client;
  plain_server.base_port = 28590;
  const std::string open_wire = wireOfASession(plain_server, plain_client, 28594);
  EXPECT_TRUE(open_wire.find("\xFF\xD8\xFF") != std::string::npos);
  EXPECT_TRUE(open_wire.find("SECRET-FAULT-TEXT") != std::string::npos);
  EXPECT_TRUE(open_wire.find("camera_model") != std::string::npos);
}

}  // namespace
}  // namespace telesphere::link
