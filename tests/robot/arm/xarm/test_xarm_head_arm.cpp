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
#include <mutex>
#include <thread>
#include <vector>

#include "robot/clock/clock.h"
#include "robot/arm/head_arm_xarm.h"
#include "robot/head/head_loop.h"
#include "robot/services/robot_health_reporter.h"
#include "robot/link/head_angles.h"
#include "robot/link/link_client.h"
#include "robot/link/link_pose.h"
#include "robot/link/link_server.h"
#include "robot/link/link_tap.h"
#include "robot/arm/xarm/controller_simulator.h"
#include "robot/arm/xarm/tcp_socket.h"
#include "robot/arm/xarm/xarm_protocol.h"
#include "tests/eventually.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;
using test::eventually;

arm::JointVector nominal() {
  arm::JointVector q;
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

  arm::XArmOptions options() const {
    arm::XArmOptions o;
    o.address = "127.0.0.1";
    o.command_port = sim->commandPort();
    o.report_port = sim->reportPort();
    o.normal_report_port = sim->normalReportPort();
    o.nominal_q = nominal();
    o.nominal_speed = 2.0;  // rad/s: a short test; a lab uses the 20°/s default
    o.nominal_acceleration = 10.0;
    return o;
  }

  std::unique_ptr<arm::XArmHeadArm> startArm(arm::XArmOptions o, std::string* error) {
    return arm::XArmHeadArm::start(o, clock, error);
  }

  void startArm() {
    std::string error;
    arm = startArm(options(), &error);
    ASSERT_TRUE(arm) << error;
  }

  /// Calls update() (as the head loop does at 100 Hz) until `status` shows.
  bool becomes(arm::ArmStatus status, std::chrono::milliseconds limit = 3000ms) {
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
    arm::JointVector q = nominal();
    auto next = std::chrono::steady_clock::now();
    for (int k = 0; k < ticks; ++k) {
      arm->update();
      q[0] += step;
      EXPECT_TRUE(arm->sendTarget(q)) << k << ": " << arm->faultText();
      next += 10ms;
      std::this_thread::sleep_until(next);
    }
  }

  clock::SteadyClock clock;
  std::unique_ptr<xarm::ControllerSimulator> sim;
  std::unique_ptr<arm::XArmHeadArm> arm;
};

TEST_F(XArmHeadArmTest, StartsUpMovesToTheNominalJointsAndStreamsServoTargets) {
  startArm();
  const auto stats = arm->stats();
  EXPECT_EQ(stats.firmware, xarm::ControllerSimulatorOptions{}.firmware);  // register 1 as the controller wrote it
  EXPECT_GT(stats.link_delay_ms, 0.0);
  auto s = sim->snapshot();
  EXPECT_TRUE(s.enabled);
  EXPECT_EQ(s.mode, std::uint8_t(xarm::ControllerMode::kServo));
  EXPECT_EQ(s.error, 0);
  EXPECT_LT((s.q_true - nominal()).cwiseAbs().maxCoeff(), 0.011);
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
  EXPECT_EQ(arm->faultText(), "");

  while (arm->pollState()) {
  }
  stream(40, 0.005);  // 0.5 rad/s on J1
  // Every target reached the controller, no more: the last may still be on its way over TCP when
  // sendTarget returns (39 of 40 seen at once under ASan beside another test).
  EXPECT_TRUE(eventually([&] { return sim->snapshot().servo_commands >= 40u; }, 2000ms));
  s = sim->snapshot();
  EXPECT_EQ(s.servo_commands, 40u);
  // The last target reaches the servos after the arm's command latency.
  EXPECT_TRUE(eventually([&] { return std::abs(sim->snapshot().set_point[0] - 0.2) < 1e-6; }, 2000ms))
      << sim->snapshot().set_point[0];
  // The reports became joint states on our clock, one per report period, in order.
  std::vector<arm::JointState> states;
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
  arm::JointVector q = nominal();
  q[1] = 3.0;  // J2 beyond 120°
  EXPECT_FALSE(arm->sendTarget(q));
  q = nominal();
  q[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(arm->sendTarget(q));
  EXPECT_EQ(arm->stats().refused_limits, 2u);
  q = nominal();
  q[2] += 0.5;  // 29° in ≤ 30 ms: beyond 180°/s
  for (int k = 0; k < 9; ++k) EXPECT_FALSE(arm->sendTarget(q));
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);  // nine refused, still streaming
  EXPECT_FALSE(arm->sendTarget(q));
  EXPECT_EQ(arm->status(), arm::ArmStatus::kStopped);
  EXPECT_NE(arm->faultText().find("J3"), std::string::npos) << arm->faultText();
  EXPECT_EQ(sim->snapshot().servo_commands, 0u);  // none of them reached the controller
  EXPECT_TRUE(arm->clearStop());
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
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
  arm::XArmOptions o = options();
  o.clear_errors = true;
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  EXPECT_EQ(sim->snapshot().error, 0);
}

TEST_F(XArmHeadArmTest, AnEmergencyStopStopsStreamingAndClearsOnlyOnceReleased) {
  startArm();
  sim->pressEmergencyStop();
  ASSERT_TRUE(becomes(arm::ArmStatus::kStopped));
  EXPECT_FALSE(arm->sendTarget(nominal()));
  ASSERT_TRUE(eventually([&] {
    arm->update();
    return arm->faultText().find("C1 emergency stop") != std::string::npos;
  })) << arm->faultText();
  EXPECT_FALSE(arm->clearStop());
  EXPECT_NE(arm->faultText().find("release the emergency stop"), std::string::npos) << arm->faultText();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kStopped);
  sim->releaseEmergencyStop();
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
  EXPECT_EQ(sim->snapshot().mode, std::uint8_t(xarm::ControllerMode::kServo));
  EXPECT_TRUE(arm->sendTarget(nominal()));
}

TEST_F(XArmHeadArmTest, ACollisionStopShowsTheControllersCodeAndClearsOnRequest) {
  startArm();
  sim->collide();
  ASSERT_TRUE(becomes(arm::ArmStatus::kStopped));
  ASSERT_TRUE(eventually([&] {
    arm->update();
    return arm->faultText() == "controller error C31 collision caused abnormal current";
  })) << arm->faultText();
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(sim->snapshot().error, 0);
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
}

TEST_F(XArmHeadArmTest, SilentReportsDisconnectAndOnlyClearStopReconnects) {
  startArm();
  sim->setReportsPaused(true);
  ASSERT_TRUE(becomes(arm::ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("no joint report"), std::string::npos) << arm->faultText();
  EXPECT_FALSE(arm->sendTarget(nominal()));
  sim->setReportsPaused(false);
  // Reports flow again (the simulator sends them) but the driver stays down until asked.
  const std::uint64_t sent = sim->snapshot().reports_sent;
  ASSERT_TRUE(eventually([&] { return sim->snapshot().reports_sent > sent + 5; }));
  arm->update();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kDisconnected);
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
  EXPECT_EQ(arm->stats().reconnects, 1u);
  EXPECT_TRUE(arm->sendTarget(nominal()));
}

TEST_F(XArmHeadArmTest, ADroppedConnectionDisconnectsAndClearStopReconnects) {
  startArm();
  sim->dropConnections();
  ASSERT_TRUE(becomes(arm::ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("closed"), std::string::npos) << arm->faultText();
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
  EXPECT_TRUE(eventually([&] { return sim->snapshot().command_clients == 1; }));
}

TEST_F(XArmHeadArmTest, UnansweredServoCommandsDisconnect) {
  startArm();
  sim->setRepliesPaused(true);
  EXPECT_TRUE(arm->sendTarget(nominal()));
  ASSERT_TRUE(becomes(arm::ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("did not answer"), std::string::npos) << arm->faultText();
  sim->setRepliesPaused(false);
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
}

TEST_F(XArmHeadArmTest, AMalformedReportDisconnectsWithTheReason) {
  startArm();
  const std::vector<std::uint8_t> garbage{0, 0, 0, 145, 0x11, 0, 0};  // a 145-byte "normal" report header
  sim->sendRawReport(garbage);
  ASSERT_TRUE(becomes(arm::ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("malformed report"), std::string::npos) << arm->faultText();
}

TEST_F(XArmHeadArmTest, AMalformedReplyDisconnectsWithTheReason) {
  startArm();
  sim->sendRawReply(std::vector<std::uint8_t>{0, 1, 0, 9, 0, 2, 13, 0});  // protocol id 9
  ASSERT_TRUE(becomes(arm::ArmStatus::kDisconnected));
  EXPECT_NE(arm->faultText().find("malformed reply"), std::string::npos) << arm->faultText();
}

TEST_F(XArmHeadArmTest, AStopRequestStopsTheControllerAndClearsOnRequest) {
  startArm();
  arm->stop();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kStopped);
  EXPECT_EQ(arm->faultText(), "stopped on request");
  EXPECT_TRUE(eventually([&] { return sim->snapshot().state == std::uint8_t(xarm::ControllerState::kStopped); }));
  EXPECT_TRUE(arm->clearStop()) << arm->faultText();
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
}

TEST_F(XArmHeadArmTest, TheControllersFaultReachesTheConsoleOverTheLinkAndItsClearFaultResumes) {
  startArm();
  head::HeadController controller;
  head::JointStateBuffer buffer(controller.config().geometry);
  link::LinkEndpoints endpoints;
  endpoints.base_port = 27680;
  link::LinkServer server(endpoints);
  link::LinkClient console(endpoints);
  head::HeadLoop loop(*arm, controller, buffer, server, clock);
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

/// The driver under the head loop on a real link: an operator app streaming head targets at
/// 100 Hz with a yaw the test sets, and a console that sends control requests and records every
/// robot state it sees.
class XArmLoop {
 public:
  XArmLoop(arm::HeadArm& arm, const clock::Clock& clock, int port) : clock_(clock) {
    endpoints_.base_port = port;
    server_ = std::make_unique<link::LinkServer>(endpoints_);
    server_->setTap(published_);
    console_ = std::make_unique<link::LinkClient>(endpoints_, link::LinkClient::Options{.frames = false});
    operator_app_ = std::make_unique<link::LinkClient>(endpoints_, link::LinkClient::Options{.frames = false});
    head::HeadLoopConfig config;
    config.auto_nominal = true;  // the first head target is the nominal pose
    loop_ = std::make_unique<head::HeadLoop>(arm, controller_, buffer_, *server_, clock, config);
    server_->setControlHandler([this](const link::proto::ControlRequest& r) { return loop_->handleControl(r); });
    head_ = std::thread([this] { loop_->run(stop_); });
    operator_ = std::thread([this] {
      std::int64_t t = 0;
      auto next = std::chrono::steady_clock::now();
      while (!stop_) {
        link::proto::HeadTarget target;
        target.set_t_ns(++t);
        target.set_t_robot_ns(clock_.nowNs());  // one process: the operator's clock is the robot's
        target.set_valid(true);
        Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
        T_vr_hmd.linear() = link::headRotationOf({yaw_deg_.load() * M_PI / 180.0, 0.0, 0.0});
        T_vr_hmd.translation() = Eigen::Vector3d(0.0, 1.6, 0.0);
        link::toLinkPose(T_vr_hmd, target.mutable_t_vr_hmd());
        operator_app_->sendHeadTarget(target);
        next += 10ms;
        std::this_thread::sleep_until(next);
      }
    });
    watcher_ = std::thread([this] {
      std::int64_t last = 0;
      while (!stop_) {
        if (const auto s = console_->latestRobotState(); s && s->t_ns() != last) {
          last = s->t_ns();
          std::lock_guard lock(mutex_);
          states_.push_back(*s);
        }
        std::this_thread::sleep_for(2ms);
      }
    });
  }
  ~XArmLoop() {
    stop_ = true;
    head_.join();
    operator_.join();
    watcher_.join();
    server_->setControlHandler(nullptr);
  }

  void setYawDeg(double yaw) { yaw_deg_ = yaw; }
  std::optional<link::proto::ControlReply> request(link::proto::ControlRequest r, std::chrono::milliseconds timeout = 5000ms) {
    return console_->request(std::move(r), timeout);
  }
  /// Waits until the newest robot state satisfies `ok`.
  bool stateBecomes(const std::function<bool(const link::proto::RobotState&)>& ok, std::chrono::milliseconds limit = 5000ms) {
    return eventually([&] {
      const auto s = console_->latestRobotState();
      return s && ok(*s);
    }, limit);
  }
  std::string fault() const {
    const auto s = console_->latestRobotState();
    return s ? s->fault() : std::string("no state");
  }
  /// Every robot state seen since `from` (an index into what was recorded).
  std::vector<link::proto::RobotState> states(std::size_t from = 0) {
    std::lock_guard lock(mutex_);
    return std::vector<link::proto::RobotState>(states_.begin() + std::ptrdiff_t(std::min(from, states_.size())), states_.end());
  }
  std::size_t stateCount() {
    std::lock_guard lock(mutex_);
    return states_.size();
  }
  const head::HeadController& controller() const { return controller_; }
  /// When the robot published its states (link clock, ns), whatever they said: a state's own
  /// t_ns is its joint measurement's and stands still while the arm is away.
  std::vector<std::int64_t> publishedStateTimesNs() const { return published_->times(); }

 private:
  class PublishedStates : public link::LinkTap {
   public:
    void onLinkMessage(Direction direction, const link::proto::Envelope& envelope,
                       const std::shared_ptr<const std::vector<std::uint8_t>>&,
                       const std::shared_ptr<const std::vector<std::uint8_t>>&) override {
      if (direction != Direction::kSent || !envelope.has_robot_state()) return;
      std::lock_guard lock(mutex_);
      times_.push_back(envelope.sender_clock_ns());
    }
    std::vector<std::int64_t> times() const {
      std::lock_guard lock(mutex_);
      return times_;
    }

   private:
    mutable std::mutex mutex_;
    std::vector<std::int64_t> times_;
  };
  std::shared_ptr<PublishedStates> published_ = std::make_shared<PublishedStates>();
  const clock::Clock& clock_;
  head::HeadController controller_;
  head::JointStateBuffer buffer_{controller_.config().geometry};
  link::LinkEndpoints endpoints_;
  std::unique_ptr<link::LinkServer> server_;
  std::unique_ptr<link::LinkClient> console_, operator_app_;
  std::unique_ptr<head::HeadLoop> loop_;
  std::atomic<bool> stop_{false};
  std::atomic<double> yaw_deg_{0.0};
  std::mutex mutex_;
  std::vector<link::proto::RobotState> states_;
  std::thread head_, operator_, watcher_;
};

/// Yaw of the head about the robot's z axis (deg) from a robot state.
double headYawDeg(const link::proto::RobotState& s) {
  const Eigen::Isometry3d T = link::fromLinkPose(s.t_robot_head());
  return std::atan2(T.linear()(1, 0), T.linear()(0, 0)) * 180.0 / M_PI;
}

TEST_F(XArmHeadArmTest, AfterAFaultTheHeadResumesFromWhereTheArmIsAndApproachesTheOperatorAtBoundedSpeed) {
  // As telesphere-robot starts it (app/robot_assembly.cpp): at the joints of the controller's
  // nominal head pose.
  const head::HeadControllerConfig config;
  const arm::Xarm6Kinematics kinematics;
  const arm::IkResult ik = kinematics.inverse(config.T_robot_nom * config.geometry.T_flange_head().inverse(),
                                         arm::JointVector::Zero(), config.ik);
  ASSERT_TRUE(ik.converged());
  arm::XArmOptions o = options();
  o.nominal_q = ik.q;
  std::string error;
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  XArmLoop rig(*arm, clock, 28240);
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.nominal_set() && s.arm_ok(); })) << rig.fault();
  // Following the operator at yaw 0 once the start-up approach from the driver's nominal joints
  // to the controller's nominal pose is over: the joints stand still.
  ASSERT_TRUE(eventually([&] {
    if (rig.stateCount() == 0) return false;
    const auto a = rig.states().back();
    std::this_thread::sleep_for(200ms);
    const auto b = rig.states().back();
    double moved = 0;
    for (int j = 0; j < 6; ++j) moved = std::max(moved, std::abs(a.joint_positions(j) - b.joint_positions(j)));
    return b.arm_ok() && moved < 1e-3;
  }, 10000ms)) << rig.fault();
  const double yaw_before = headYawDeg(rig.states().back());

  sim->collide();
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return !s.arm_ok(); })) << rig.fault();
  // The operator turns 40° while the arm stands; the targets keep streaming.
  for (int k = 1; k <= 50; ++k) {
    rig.setYawDeg(40.0 * k / 50.0);
    std::this_thread::sleep_for(20ms);
  }
  const std::uint64_t refused_before = arm->stats().refused_jumps;
  const std::size_t from = rig.stateCount();
  link::proto::ControlRequest clear;
  clear.set_clear_fault(true);
  const auto reply = rig.request(clear);
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok()) << reply->error();
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.arm_ok(); })) << rig.fault();
  // The head reaches where the operator looks now, approaching it at the controller's speed.
  const double approach_deg_s = rig.controller().config().approach_angular_speed * 180.0 / M_PI;
  ASSERT_TRUE(rig.stateBecomes([&](const auto& s) { return std::abs(headYawDeg(s) - yaw_before - 40.0) < 1.0; },
                               std::chrono::milliseconds(int(1000.0 * 40.0 / approach_deg_s) + 3000)))
      << "head yaw " << headYawDeg(rig.states().back()) - yaw_before << "°, " << rig.fault() << ", unreachable targets "
      << rig.controller().unreachableCount();
  std::this_thread::sleep_for(300ms);

  const auto after = rig.states(from);
  bool ok_seen = false;
  int second_faults = 0;
  double joint_speed_max = 0, head_speed_max = 0;
  for (std::size_t i = 0; i < after.size(); ++i) {
    ok_seen = ok_seen || after[i].arm_ok();
    if (ok_seen && !after[i].arm_ok()) ++second_faults;
    if (i == 0 || !after[i].arm_ok() || !after[i - 1].arm_ok()) continue;
    const double dt = double(after[i].t_ns() - after[i - 1].t_ns()) * 1e-9;
    if (dt <= 0) continue;
    for (int j = 0; j < 6; ++j)
      joint_speed_max = std::max(joint_speed_max,
                                 std::abs(after[i].joint_positions(j) - after[i - 1].joint_positions(j)) / dt * 180.0 / M_PI);
    head_speed_max = std::max(head_speed_max, std::abs(headYawDeg(after[i]) - headYawDeg(after[i - 1])) / dt);
  }
  std::printf("resume: head yaw speed max %.1f°/s (approach %.1f°/s), joint speed max %.1f°/s, %zu states\n",
              head_speed_max, approach_deg_s, joint_speed_max, after.size());
  EXPECT_EQ(second_faults, 0) << rig.fault();
  EXPECT_EQ(arm->stats().refused_jumps, refused_before) << "the driver refused targets that jumped";
  // The slow approach, with the 50 Hz states' sampling and the arm's own lag as margin. The joints
  // turning the head in place move faster than the head (about 130°/s for its 45°/s here), but
  // below their top speed, at which a swing toward the operator would move them.
  EXPECT_LT(head_speed_max, 1.5 * approach_deg_s);
  EXPECT_LT(joint_speed_max, 0.9 * o.max_velocity * 180.0 / M_PI);
}

TEST_F(XArmHeadArmTest, AConsoleStopNeverHidesTheArmsOwnFault) {
  startArm();
  XArmLoop rig(*arm, clock, 28250);
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.arm_ok(); })) << rig.fault();
  link::proto::ControlRequest stop;
  stop.set_arm_stop(true);
  // The console stops the arm, then the emergency stop is pressed: the arm's cause comes first.
  ASSERT_TRUE(rig.request(stop));
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.fault() == "arm stopped from the console"; })) << rig.fault();
  sim->pressEmergencyStop();
  EXPECT_TRUE(rig.stateBecomes([](const auto& s) {
    return s.fault() ==
           "arm stopped: controller error C1 emergency stop button on the controller pushed in; also stopped from the console";
  })) << rig.fault();
  // Cleared only once released; then the console stops it again after an emergency stop.
  sim->releaseEmergencyStop();
  link::proto::ControlRequest clear;
  clear.set_clear_fault(true);
  ASSERT_TRUE(rig.request(clear));
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.arm_ok(); })) << rig.fault();
  sim->pressEmergencyStop();
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.fault().find("C1 emergency stop") != std::string::npos; }))
      << rig.fault();
  ASSERT_TRUE(rig.request(stop));
  EXPECT_TRUE(rig.stateBecomes([](const auto& s) {
    return s.fault().rfind("arm stopped: controller error C1", 0) == 0 &&
           s.fault().find("; also stopped from the console") != std::string::npos;
  })) << rig.fault();
  sim->releaseEmergencyStop();
}

TEST_F(XArmHeadArmTest, ClearingAFaultOnAnUnansweringControllerNeverFreezesTheRobot) {
  arm::XArmOptions o = options();
  o.reply_timeout = 1500ms;
  std::string error;
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  XArmLoop rig(*arm, clock, 28260);
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return s.arm_ok(); })) << rig.fault();
  // The controller stops answering and its connections drop: a reconnect connects, then waits
  // for replies that never come (1.5 s per request).
  sim->setRepliesPaused(true);
  sim->dropConnections();
  ASSERT_TRUE(rig.stateBecomes([](const auto& s) { return !s.arm_ok(); })) << rig.fault();
  const std::size_t from = rig.publishedStateTimesNs().size();
  link::proto::ControlRequest clear;
  clear.set_clear_fault(true);
  const auto t0 = std::chrono::steady_clock::now();
  const auto reply = rig.request(clear);
  const auto reply_ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok());
  EXPECT_TRUE(reply->pending());
  EXPECT_LT(reply_ms, 500) << "the clear request waited for the reconnect";
  EXPECT_TRUE(rig.stateBecomes([](const auto& s) { return s.fault().rfind("clearing the fault", 0) == 0; })) << rig.fault();
  // Meanwhile the link serves: another request is answered at once, states keep coming.
  link::proto::ControlRequest settings;
  settings.set_get_settings(true);
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_TRUE(rig.request(settings));
  EXPECT_LT(std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t1).count(), 500);
  // The reconnect fails (no reply to its first request) and says so.
  EXPECT_TRUE(rig.stateBecomes([](const auto& s) { return s.fault().find("cannot resume") != std::string::npos; }, 8000ms))
      << rig.fault();
  const auto published = rig.publishedStateTimesNs();
  ASSERT_GE(published.size(), from + 2);
  std::int64_t gap_max_ns = 0;
  for (std::size_t i = from + 1; i < published.size(); ++i)
    gap_max_ns = std::max(gap_max_ns, published[i] - published[i - 1]);
  std::printf("during the failing reconnect: %zu states published, largest gap %.0f ms\n", published.size() - from,
              double(gap_max_ns) * 1e-6);
  EXPECT_LT(gap_max_ns, 300'000'000) << "robot states stopped during the reconnect";
  // Replies again: the next clear reconnects.
  sim->setRepliesPaused(false);
  ASSERT_TRUE(rig.request(clear));
  EXPECT_TRUE(rig.stateBecomes([](const auto& s) { return s.arm_ok(); }, 8000ms)) << rig.fault();
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
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk);
}

// Issue #30: the simulator answers as a controller does, and the driver speaks what the firmware
// it finds expects.
TEST_F(XArmHeadArmTest, SpeaksTheIdentifierItsFirmwareExpectsAndTheSimulatorEchoesIt) {
  startArm();  // the simulator's firmware is v2.3.0: identifier 3
  EXPECT_EQ(arm->stats().protocol, xarm::kPrivateProtocolWithHeartbeat);
  EXPECT_EQ(sim->snapshot().last_protocol, xarm::kPrivateProtocolWithHeartbeat);
  EXPECT_EQ(arm->stats().serial, "XI120204201B02");
  EXPECT_EQ(arm->stats().firmware, "6,6,XI1202,AC1302,v2.3.0");
  stream(20, 0.002);
  EXPECT_EQ(arm->status(), arm::ArmStatus::kOk) << arm->faultText();
  arm.reset();

  // Older firmware: identifier 2 throughout.
  xarm::ControllerSimulatorOptions old_options;
  old_options.firmware = "6,6,XI1202,AC1302,v1.8.5";
  std::string error;
  auto old_sim = xarm::ControllerSimulator::start(old_options, &error);
  ASSERT_TRUE(old_sim) << error;
  arm::XArmOptions o = options();
  o.command_port = old_sim->commandPort();
  o.report_port = old_sim->reportPort();
  o.normal_report_port = old_sim->normalReportPort();
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  EXPECT_EQ(arm->stats().protocol, xarm::kPrivateProtocol);
  EXPECT_EQ(old_sim->snapshot().last_protocol, xarm::kPrivateProtocol);
  arm.reset();

  // Raw bytes: a request with identifier 3 is answered with 3, one with 2 with 2; the old
  // heartbeat frame is taken without a reply.
  auto raw = xarm::TcpSocket::connect("127.0.0.1", sim->commandPort(), 1000ms, &error);
  ASSERT_TRUE(raw) << error;
  for (std::uint16_t id : {xarm::kPrivateProtocolWithHeartbeat, xarm::kPrivateProtocol}) {
    const std::vector<std::uint8_t> heartbeat{0x00, 0x00, 0x00, 0x01, 0x00, 0x02, 0x00, 0x00};
    ASSERT_TRUE(raw->sendAll(heartbeat, 1000ms, &error));
    ASSERT_TRUE(raw->sendAll(xarm::encodeRequest(42, xarm::Register::kGetState, {}, id), 1000ms, &error));
    xarm::FrameReader reader;
    std::vector<std::uint8_t> buffer(64);
    std::optional<xarm::Frame> reply;
    for (int i = 0; i < 100 && !reply; ++i) {
      std::size_t n = 0;
      if (raw->receive(buffer, 20ms, &n, &error) == xarm::TcpSocket::Received::kData)
        reader.feed(std::span<const std::uint8_t>(buffer.data(), n));
      reply = reader.next();
    }
    ASSERT_TRUE(reply);
    EXPECT_EQ(reply->transaction, 42);  // the heartbeat had no reply: this is the first frame
    EXPECT_EQ(reply->protocol, id);
    EXPECT_EQ(reply->reg, std::uint8_t(xarm::Register::kGetState));
  }
  EXPECT_EQ(sim->snapshot().heartbeats, 2u);
}

TEST_F(XArmHeadArmTest, AnIdentifier3ConnectionIsKeptInUseWhileTheDriverWaits) {
  // A controller that drops an identifier-3 client silent for 300 ms, and a nominal move that
  // takes about 1.5 s: the driver's keepalive requests carry it through; without them it fails.
  sim.reset();
  xarm::ControllerSimulatorOptions strict;
  strict.id3_silence_limit = 300ms;
  std::string error;
  sim = xarm::ControllerSimulator::start(strict, &error);
  ASSERT_TRUE(sim) << error;
  arm::XArmOptions o = options();
  o.nominal_speed = 0.3;  // rad/s: J3's 0.4 rad take about 1.3 s
  o.keepalive = 100ms;
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  arm.reset();
  o.keepalive = 10000ms;
  o.nominal_q = arm::JointVector::Zero();  // back again: another 1.3 s move, silent this time
  EXPECT_FALSE(startArm(o, &error));
  EXPECT_NE(error.find("closed the command connection"), std::string::npos) << error;
}

TEST_F(XArmHeadArmTest, SetsThePayloadAndSensitivityReadsThemBackAndReportsThemInHealth) {
  arm::XArmOptions o = options();
  o.payload_kg = 1.25;
  o.payload_com_mm = {0.0, 5.0, 62.0};
  o.collision_sensitivity = 2;
  std::string error;
  arm = startArm(o, &error);
  ASSERT_TRUE(arm) << error;
  const auto snap = sim->snapshot();
  EXPECT_NEAR(snap.payload_kg, 1.25, 1e-6);
  EXPECT_NEAR(snap.payload_com_mm[2], 62.0, 1e-4);
  EXPECT_EQ(snap.collision_sensitivity, 2);
  const auto stats = arm->stats();
  EXPECT_TRUE(stats.payload_read) << stats.readback_error;
  EXPECT_NEAR(stats.payload_kg, 1.25, 1e-6);
  EXPECT_EQ(stats.collision_sensitivity, 2);
  // The console's health view gets the driver's figures.
  services::RobotHealthSources sources;
  sources.xarm = arm.get();
  sources.arm = "xArm 6";
  services::RobotHealthReporter reporter(sources, clock);
  stream(10, 0.002);
  const link::proto::RobotHealth health = reporter.make();
  ASSERT_TRUE(health.has_xarm());
  EXPECT_EQ(health.xarm().serial(), "XI120204201B02");
  EXPECT_EQ(health.xarm().protocol(), 3u);
  EXPECT_GT(health.xarm().link_delay_ms(), 0.0);
  EXPECT_GE(health.xarm().reports(), 10u);
  EXPECT_EQ(health.xarm().targets_sent(), 10u);
  EXPECT_NEAR(health.xarm().payload_kg(), 1.25, 1e-6);
  EXPECT_NEAR(health.xarm().payload_com_z_mm(), 62.0, 1e-4);
  EXPECT_EQ(health.xarm().collision_sensitivity(), 2);
  arm.reset();

  // A controller that does not take the payload: the start-up stops and says both values.
  sim->setPayloadWritesIgnored(true);
  o.payload_kg = 0.8;
  EXPECT_FALSE(startArm(o, &error));
  EXPECT_NE(error.find("reports a payload of 1.250 kg"), std::string::npos) << error;
  EXPECT_NE(error.find("configured 0.800 kg"), std::string::npos) << error;
}

TEST(XArmHeadArmStart, NobodyListeningFailsWithTheAddressAndAHint) {
  std::string error;
  int port = 0;
  {
    auto listener = xarm::TcpListener::listen("127.0.0.1", 0, &error);  // a port that was free a moment ago
    ASSERT_TRUE(listener) << error;
    port = listener->port();
  }
  clock::SteadyClock clock;
  arm::XArmOptions o;
  o.address = "127.0.0.1";
  o.command_port = port;
  o.connect_timeout = 1000ms;
  EXPECT_FALSE(arm::XArmHeadArm::start(o, clock, &error));
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error;
  EXPECT_NE(error.find("refused"), std::string::npos) << error;
  o.address.clear();
  EXPECT_FALSE(arm::XArmHeadArm::start(o, clock, &error));
  EXPECT_NE(error.find("--arm-address"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::robot
