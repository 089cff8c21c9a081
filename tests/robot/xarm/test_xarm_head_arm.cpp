// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm, the real xArm 6's driver, against the protocol simulator over real TCP
///        sockets on loopback: start-up (version, link delay, errors, the nominal move, servo
///        mode), streaming and the stamped joint states, the refusals (limits, not finite, jumps),
///        every fault a controller shows (emergency stop, collision, silent reports, silent
///        replies, a dropped connection, malformed reports and replies, nobody listening), that
///        nothing reconnects or clears until clearStop() asks, and a controller fault reaching the
///        console over the link (HeadLoop) with its "clear fault" resuming.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "robot/clock.h"
#include "robot/head_arm_xarm.h"
#include "robot/head_loop.h"
#include "robot/link/link_client.h"
#include "robot/link/link_server.h"
#include "robot/xarm/controller_simulator.h"
#include "robot/xarm/tcp_socket.h"
#include "robot/xarm/xarm_protocol.h"
#include "tests/eventually.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;
using test::eventually;

JointVector nominal() {
  JointVector q;
  q << 0.0, -0.2, -0.4, 0.0, 0.3, 0.0;
  return q;
}

class XArmHeadArmTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    sim = xarm::ControllerSimulator::start({}, &error);
    ASSERT_TRUE(sim) << error;
  }

  XArmOptions options() const {
    XArmOptions o;
    o.address = "127.0.0.1";
    o.command_port = sim->commandPort();
    o.report_port = sim->reportPort();
    o.nominal_q = nominal();
    o.nominal_speed = 2.0;  // rad/s: a short test; a lab uses the 20°/s default
    o.nominal_acceleration = 10.0;
    return o;
  }

  std::unique_ptr<XArmHeadArm> startArm(XArmOptions o, std::string* error) {
    return XArmHeadArm::start(o, clock, error);
  }

  void startArm() {
    std::string error;
    arm = startArm(options(), &error);
    ASSERT_TRUE(arm) << error;
  }

  /// Calls update() (as the head loop does at 100 Hz) until `status` shows.
  bool becomes(ArmStatus status, std::chrono::milliseconds limit = 3000ms) {
    return eventually(
        [&] {
          arm->update();
          while (arm->pollState()) {
          }
          return arm->status() == status;
        },
        limit);
  }

  /// Streams targets at 100 Hz from the nominal joints along J1 by `step` rad per tick.
  void stream(int ticks, double step) {
    JointVector q = nominal();
    auto next = std::chrono::steady_clock::now();
    for (int k = 0; k < ticks; ++k) {
      arm->update();
      q[0] += step;
      EXPECT_TRUE(arm->sendTarget(q)) << k << ": " << arm->faultText();
      next += 10ms;
      std::this_thread::sleep_until(next);
    }
  }

  SteadyClock clock;
  std::unique_ptr<xarm::ControllerSimulator> sim;
  std::unique_ptr<XArmHeadArm> arm;
};

TEST_F(XArmHeadArmTest, StartsUpMovesToTheNominalJointsAndStreamsServoTargets) {
  startArm();
  const auto stats = arm->stats();
  EXPECT_NE(stats.firmware.find("telesphere-simulator"), std::string::npos) << stats.firmware;
  EXPECT_GT(stats.link_delay_ms, 0.0);
  auto s = sim->snapshot();
  EXPECT_TRUE(s.enabled);
  EXPECT_EQ(s.mode, std::uint8_t(xarm::ControllerMode::kServo));
  EXPECT_EQ(s.error, 0);
  EXPECT_LT((s.q_true - nominal()).cwiseAbs().maxCoeff(), 0.011);
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
  EXPECT_EQ(arm->faultText(), "");

  while (arm->pollState()) {
  }
  stream(40, 0.005);  // 0.5 rad/s on J1
  s = sim->snapshot();
  EXPECT_EQ(s.servo_commands, 40u);
  // The last target reaches the servos after the arm's command latency.
  EXPECT_TRUE(eventually([&] { return std::abs(sim->snapshot().set_point[0] - 0.2) < 1e-6; }, 2000ms))
      << sim->snapshot().set_point[0];
  // The reports became joint states on our clock, one per report period, in order.
  std::vector<JointState> states;
  while (auto st = arm->pollState()) states.push_back(*st);
  ASSERT_GE(states.size(), 30u);
  for (std::size_t i = 1; i < states.size(); ++i) {
    EXPECT_GT(states[i].t_ns, states[i - 1].t_ns);
    // The fitted report grid (its offset moves only when a faster arrival lowers the envelope).
    EXPECT_NEAR(double(states[i].t_ns - states[i - 1].t_ns), 10e6, 2e6) << i;
  }
  EXPECT_LE(states.back().t_ns, clock.nowNs());
  EXPECT_EQ(arm->stats().targets_sent, 40u);
}

TEST_F(XArmHeadArmTest, RefusesTargetsOutsideTheLimitsNotFiniteOrJumpingAndStopsAfterTenJumps) {
  startArm();
  JointVector q = nominal();
  q[1] = 3.0;  // J2 beyond 120°
  EXPECT_FALSE(arm->sendTarget(q));
  q = nominal();
  q[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(arm->sendTarget(q));
  EXPECT_EQ(arm->stats().refused_limits, 2u);
  q = nominal();
  q[2] += 0.5;  // 29° in ≤ 30 ms: beyond 180°/s
  for (int k = 0; k < 9; ++k) EXPECT_FALSE(arm->sendTarget(q));
  EXPECT_EQ(arm->status(), ArmStatus::kOk);  // nine refused, still streaming
  EXPECT_FALSE(arm->sendTarget(q));
  EXPECT_EQ(arm->status(), ArmStatus::kStopped);
  EXPECT_NE(arm->faultText().find("J3"), std::string::npos) << arm->faultText();
  EXPECT_EQ(sim->snapshot().servo_commands, 0u);  // none of them reached the controller
  EXPECT_TRUE(arm->clearStop());
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
  q = nominal();
  q[2] += 0.01;  // a step the joints can take
  EXPECT_TRUE(arm->sendTarget(q));
}

TEST_F(XArmHeadArmTest, AControllerErrorAtStartUpIsClearedOnlyWhenTheSupervisorAsks) {
  sim->collide();
  std::string error;
  EXPECT_FALSE(startArm(options(), &error));
  EXPECT_NE(error.find("C31 collision caused abnormal current"), std::string::npos) << error;
  EXPECT_EQ(sim->snapshot().error, 31);  // left as it was
  XArmOptions o = options();
  o.clear_errors = true;
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  EXPECT_EQ(sim->snapshot().error, 0);
}

TEST_F(XArmHeadArmTest, AnEmergencyStopStopsStreamingAndClearsOnlyOnceReleased) {
  startArm();
  sim->pressEmergencyStop();
  ASSERT_TRUE(becomes(ArmStatus::kStopped));
  EXPECT_FALSE(arm->sendTarget(nominal()));
  ASSERT_TRUE(eventually([&] {
    arm->update();
    return arm->faultText().find("C1 emergency stop") != std::string::npos;
  })) << arm->faultText();
  EXPECT_FALSE(arm->clearStop());
  EXPECT_NE(arm->faultText().find("release the emergency stop"), std::string::npos) << arm->faultText();
  EXPECT_EQ(arm->status(), ArmStatus::kStopped);
  sim->releaseEmergencyStop();
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
  EXPECT_EQ(sim->snapshot().mode, std::uint8_t(xarm::ControllerMode::kServo));
  EXPECT_TRUE(arm->sendTarget(nominal()));
}

TEST_F(XArmHeadArmTest, ACollisionStopShowsTheControllersCodeAndClearsOnRequest) {
  startArm();
  sim->collide();
  ASSERT_TRUE(becomes(ArmStatus::kStopped));
  ASSERT_TRUE(eventually([&] {
    arm->update();
    return arm->faultText() == "controller error C31 collision caused abnormal current";
  })) << arm->faultText();
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(sim->snapshot().error, 0);
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
}

TEST_F(XArmHeadArmTest, SilentReportsDisconnectAndOnlyClearStopReconnects) {
  startArm();
  sim->setReportsPaused(true);
  ASSERT_TRUE(becomes(ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("no joint report"), std::string::npos) << arm->faultText();
  EXPECT_FALSE(arm->sendTarget(nominal()));
  sim->setReportsPaused(false);
  // Reports flow again (the simulator sends them) but the driver stays down until asked.
  const std::uint64_t sent = sim->snapshot().reports_sent;
  ASSERT_TRUE(eventually([&] { return sim->snapshot().reports_sent > sent + 5; }));
  arm->update();
  EXPECT_EQ(arm->status(), ArmStatus::kDisconnected);
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
  EXPECT_EQ(arm->stats().reconnects, 1u);
  EXPECT_TRUE(arm->sendTarget(nominal()));
}

TEST_F(XArmHeadArmTest, ADroppedConnectionDisconnectsAndClearStopReconnects) {
  startArm();
  sim->dropConnections();
  ASSERT_TRUE(becomes(ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("closed"), std::string::npos) << arm->faultText();
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
  EXPECT_TRUE(eventually([&] { return sim->snapshot().command_clients == 1; }));
}

TEST_F(XArmHeadArmTest, UnansweredServoCommandsDisconnect) {
  startArm();
  sim->setRepliesPaused(true);
  EXPECT_TRUE(arm->sendTarget(nominal()));
  ASSERT_TRUE(becomes(ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("did not answer"), std::string::npos) << arm->faultText();
  sim->setRepliesPaused(false);
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
}

TEST_F(XArmHeadArmTest, AMalformedReportDisconnectsWithTheReason) {
  startArm();
  const std::vector<std::uint8_t> garbage{0, 0, 0, 145, 0x11, 0, 0};  // a 145-byte "normal" report header
  sim->sendRawReport(garbage);
  ASSERT_TRUE(becomes(ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("malformed report"), std::string::npos) << arm->faultText();
}

TEST_F(XArmHeadArmTest, AMalformedReplyDisconnectsWithTheReason) {
  startArm();
  sim->sendRawReply(std::vector<std::uint8_t>{0, 1, 0, 9, 0, 2, 13, 0});  // protocol id 9
  ASSERT_TRUE(becomes(ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("malformed reply"), std::string::npos) << arm->faultText();
}

TEST_F(XArmHeadArmTest, AStopRequestStopsTheControllerAndClearsOnRequest) {
  startArm();
  arm->stop();
  EXPECT_EQ(arm->status(), ArmStatus::kStopped);
  EXPECT_EQ(arm->faultText(), "stopped on request");
  EXPECT_TRUE(eventually([&] { return sim->snapshot().state == std::uint8_t(xarm::ControllerState::kStopped); }));
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
}

TEST_F(XArmHeadArmTest, TheControllersFaultReachesTheConsoleOverTheLinkAndItsClearFaultResumes) {
  startArm();
  HeadController controller;
  JointStateBuffer buffer(controller.config().geometry);
  link::LinkEndpoints endpoints;
  endpoints.base_port = 27680;
  link::LinkServer server(endpoints);
  link::LinkClient console(endpoints);
  HeadLoop loop(*arm, controller, buffer, server, clock);
  server.setControlHandler([&loop](const link::proto::ControlRequest& r) { return loop.handleControl(r); });
  std::atomic<bool> stop{false};
  std::thread head([&] { loop.run(stop); });
  const auto armOk = [&](bool ok) {
    return eventually([&] {
      const auto s = console.latestRobotState();
      return s && s->arm_ok() == ok;
    });
  };
  EXPECT_TRUE(armOk(true));
  sim->collide();
  EXPECT_TRUE(eventually([&] {
    const auto s = console.latestRobotState();
    return s && s->fault() == "arm stopped: controller error C31 collision caused abnormal current";
  })) << (console.latestRobotState() ? console.latestRobotState()->fault() : std::string("no state"));
  link::proto::ControlRequest clear;
  clear.set_clear_fault(true);
  const auto reply = console.request(clear, 5000ms);
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok()) << reply->error();
  EXPECT_TRUE(armOk(true));
  EXPECT_EQ(sim->snapshot().error, 0);
  stop = true;
  head.join();
  server.setControlHandler(nullptr);
}

TEST_F(XArmHeadArmTest, TheSimulatorDropsAClientThatSendsGarbageAndServesTheNextOne) {
  std::string error;
  auto raw = xarm::TcpSocket::connect("127.0.0.1", sim->commandPort(), 1000ms, &error);
  ASSERT_TRUE(raw) << error;
  const std::vector<std::uint8_t> garbage{0, 1, 0, 9, 0, 2, 13, 0};  // protocol id 9
  ASSERT_TRUE(raw->sendAll(garbage, 1000ms, &error)) << error;
  std::vector<std::uint8_t> buffer(64);
  std::size_t n = 0;
  xarm::TcpSocket::Received got = xarm::TcpSocket::Received::kTimeout;
  for (int i = 0; i < 100 && got == xarm::TcpSocket::Received::kTimeout; ++i) got = raw->receive(buffer, 20ms, &n, &error);
  EXPECT_EQ(got, xarm::TcpSocket::Received::kClosed);
  // A truncated request, then the connection gone: nothing breaks.
  auto truncated = xarm::TcpSocket::connect("127.0.0.1", sim->commandPort(), 1000ms, &error);
  ASSERT_TRUE(truncated) << error;
  const auto request = xarm::encodeRequest(5, xarm::Register::kGetState, {});
  ASSERT_TRUE(truncated->sendAll(std::span(request).first(4), 1000ms, &error));
  truncated->close();
  // The next client is served as usual.
  startArm();
  EXPECT_EQ(arm->status(), ArmStatus::kOk);
}

TEST(XArmHeadArmStart, NobodyListeningFailsWithTheAddressAndAHint) {
  std::string error;
  int port = 0;
  {
    auto listener = xarm::TcpListener::listen("127.0.0.1", 0, &error);  // a port that was free a moment ago
    ASSERT_TRUE(listener) << error;
    port = listener->port();
  }
  SteadyClock clock;
  XArmOptions o;
  o.address = "127.0.0.1";
  o.command_port = port;
  o.connect_timeout = 1000ms;
  EXPECT_FALSE(XArmHeadArm::start(o, clock, &error));
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error;
  EXPECT_NE(error.find("refused"), std::string::npos) << error;
  o.address.clear();
  EXPECT_FALSE(XArmHeadArm::start(o, clock, &error));
  EXPECT_NE(error.find("--arm-address"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::robot
