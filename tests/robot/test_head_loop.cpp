// SPDX-License-Identifier: MIT
/// @brief HeadLoop on a real link (loopback ZeroMQ) with the simulated arm in simulated time:
///        the nominal pose is captured through a control request, head targets from the client
///        move the arm, robot state reaches the client, and bad control requests are refused
///        with a reason.
#include <gtest/gtest.h>

#include <thread>

#include "tests/eventually.h"
#include "robot/head_arm_sim.h"
#include "robot/head_loop.h"
#include "robot/link/link_client.h"
#include "robot/sim_clock.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

using ::telesphere::test::eventually;

link::proto::HeadTarget target(std::int64_t t_ns, const Eigen::Vector3d& position) {
  link::proto::HeadTarget t;
  t.set_t_ns(t_ns);
  t.set_valid(true);
  auto* pose = t.mutable_t_vr_hmd();
  pose->set_tx(position.x());
  pose->set_ty(position.y());
  pose->set_tz(position.z());
  pose->set_qw(1.0);
  return t;
}

struct HeadLoopRig {
  SimClock clock{1'000'000'000};
  SimulatedArmConfig arm_config;
  SimulatedArm arm{clock, armConfig()};
  HeadController controller;
  JointStateBuffer buffer{controller.config().geometry};
  link::LinkEndpoints endpoints;
  std::unique_ptr<link::LinkServer> server;
  std::unique_ptr<link::LinkClient> client;
  std::unique_ptr<HeadLoop> loop;
  std::int64_t operator_t_ns = 1;

  static SimulatedArmConfig armConfig() {
    SimulatedArmConfig c;
    c.q_initial << 0.0, -0.3, -0.6, 0.0, 0.9, 0.0;
    return c;
  }

  explicit HeadLoopRig(int port) {
    endpoints.base_port = port;
    server = std::make_unique<link::LinkServer>(endpoints);
    client = std::make_unique<link::LinkClient>(endpoints);
    loop = std::make_unique<HeadLoop>(arm, controller, buffer, *server, clock);
    server->setControlHandler([this](const link::proto::ControlRequest& r) { return loop->handleControl(r); });
  }

  /// Sends a target until the server holds it: the uplink is asynchronous and, like the XR app
  /// sending every display frame, drops a target while it (re)connects instead of queueing it.
  void sendTarget(const Eigen::Vector3d& position) {
    const std::int64_t t = ++operator_t_ns;
    ASSERT_TRUE(eventually([&] {
      client->sendHeadTarget(target(t, position));
      std::this_thread::sleep_for(1ms);
      const auto latest = server->latestHeadTarget();
      return latest && latest->t_ns() == t;
    }));
  }

  void step() {
    clock.advance(10'000'000);
    loop->tick();
  }

  link::proto::ControlReply request(link::proto::ControlRequest r) {
    auto reply = client->request(std::move(r), 3000ms);
    EXPECT_TRUE(reply);
    return reply ? *reply : link::proto::ControlReply{};
  }
};

TEST(HeadLoop, NominalCaptureThenTargetsMoveTheArm) {
  HeadLoopRig rig(27200);
  link::proto::ControlRequest capture;
  capture.set_capture_nominal(true);
  // Nothing from the headset yet: refused with a reason.
  const auto early = rig.request(capture);
  EXPECT_FALSE(early.ok());
  EXPECT_NE(early.error().find("no head target"), std::string::npos) << early.error();

  const Eigen::Vector3d head(0.0, 1.6, 0.0);
  rig.sendTarget(head);
  rig.step();
  EXPECT_TRUE(rig.request(capture).ok());
  rig.sendTarget(head);
  rig.step();
  ASSERT_TRUE(rig.controller.initialised());
  // The arm first approaches the nominal pose from wherever it was.
  for (int i = 0; i < 300; ++i) {
    rig.sendTarget(head);
    rig.step();
  }
  const Eigen::Vector3d p0 =
      rig.controller.kinematics().forward(rig.arm.trueJoints()).translation();

  // The operator moves 5 cm; the arm follows within a second (paper: ~130 ms).
  for (int i = 0; i < 100; ++i) {
    rig.sendTarget(head + Eigen::Vector3d(0.05, 0.0, 0.0));
    rig.step();
  }
  const Eigen::Vector3d p1 =
      rig.controller.kinematics().forward(rig.arm.trueJoints()).translation();
  EXPECT_NEAR((p1 - p0).norm(), 0.05, 0.01);
  EXPECT_GT(rig.loop->targetsSent(), 50);
  // The robot state tells the operator's app the nominal mapping it renders with.
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->nominal_set();
  }));
  const auto state = *rig.client->latestRobotState();  // a copy: the accessor returns by value
  const auto& T = state.t_robot_vr();
  EXPECT_NEAR(T.tx(), rig.controller.T_robot_vr().translation().x(), 1e-12);
  EXPECT_NEAR(T.qw() * T.qw() + T.qx() * T.qx() + T.qy() * T.qy() + T.qz() * T.qz(), 1.0, 1e-9);
  // The joint-state buffer the video path reads was filled on the way.
  EXPECT_GT(rig.buffer.size(), 300u);
  EXPECT_TRUE(rig.buffer.T_robot_cam(CameraSide::kLeft, rig.clock.nowNs() - 20'000'000));
}

TEST(HeadLoop, RobotStateReachesTheClientAndControlRequestsAreChecked) {
  HeadLoopRig rig(27210);
  link::proto::ControlRequest mode;
  mode.set_set_mode("orientation3d");
  EXPECT_TRUE(rig.request(mode).ok());
  mode.set_set_mode("bogus");
  const auto bad_mode = rig.request(mode);
  EXPECT_FALSE(bad_mode.ok());
  EXPECT_NE(bad_mode.error().find("bogus"), std::string::npos);

  link::proto::ControlRequest radius;
  radius.set_set_sphere_radius(0.01);
  EXPECT_FALSE(rig.request(radius).ok());
  radius.set_set_sphere_radius(2.5);
  EXPECT_TRUE(rig.request(radius).ok());
  EXPECT_FALSE(rig.request(link::proto::ControlRequest{}).ok());

  // A SUB joins late: keep ticking until a state arrives.
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->sphere_radius() == 2.5;
  }));
  const auto state = *rig.client->latestRobotState();
  EXPECT_EQ(state.mode(), "orientation3d");
  EXPECT_EQ(state.joint_positions_size(), 6);
  EXPECT_TRUE(state.arm_ok());
  EXPECT_NEAR(state.joint_positions(1), -0.3, 0.01);
  EXPECT_FALSE(state.nominal_set());  // no head target, no nominal pose

  rig.arm.triggerStop();
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && !s->arm_ok();
  }));
  EXPECT_FALSE(rig.client->latestRobotState()->fault().empty());
}

}  // namespace
}  // namespace telesphere::robot
