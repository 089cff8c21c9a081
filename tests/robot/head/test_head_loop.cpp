// SPDX-License-Identifier: MIT
/// @brief HeadLoop on a real link (loopback ZeroMQ) with the simulated arm in simulated time:
///        the nominal pose is captured through a control request, head targets from the client
///        move the arm, robot state reaches the client, and bad control requests are refused
///        with a reason.
#include <gtest/gtest.h>

#include <thread>

#include "tests/eventually.h"
#include "robot/arm/head_arm_sim.h"
#include "robot/head/head_loop.h"
#include "robot/head/calibration_head_pattern.h"
#include "robot/link/head_angles.h"
#include "robot/link/link_client.h"
#include "robot/link/link_pose.h"
#include "robot/clock/sim_clock.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

using ::telesphere::test::eventually;

link::proto::HeadTarget target(std::int64_t t_ns, const Eigen::Vector3d& position,
                               const link::HeadAngles& angles = {}, std::int64_t t_robot_ns = 0) {
  link::proto::HeadTarget t;
  t.set_t_ns(t_ns);
  t.set_t_robot_ns(t_robot_ns);
  t.set_valid(true);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = link::headRotationOf(angles);
  T.translation() = position;
  link::toLinkPose(T, t.mutable_t_vr_hmd());
  return t;
}

struct HeadLoopRig {
  clock::SimClock clock{1'000'000'000};
  arm::SimulatedArmConfig arm_config;
  arm::SimulatedArm arm{clock, armConfig()};
  head::HeadController controller;
  head::JointStateBuffer buffer{controller.config().geometry};
  link::LinkEndpoints endpoints;
  std::unique_ptr<link::LinkServer> server;
  std::unique_ptr<link::LinkClient> client;
  std::unique_ptr<head::HeadLoop> loop;
  std::int64_t operator_t_ns = 1;

  static arm::SimulatedArmConfig armConfig() {
    arm::SimulatedArmConfig c;
    c.q_initial << 0.0, -0.3, -0.6, 0.0, 0.9, 0.0;
    return c;
  }

  telemetry::TelemetryBatcher telemetry;

  /// `hold_lease_ns`: how long a calibration hold lasts without a renewal.
  explicit HeadLoopRig(int port, std::int64_t hold_lease_ns = head::HeadLoopConfig{}.hold_lease_ns) {
    endpoints.base_port = port;
    server = std::make_unique<link::LinkServer>(endpoints);
    client = std::make_unique<link::LinkClient>(endpoints, link::LinkClient::Options{.telemetry = true});
    head::HeadLoopConfig config;
    config.telemetry = &telemetry;
    config.hold_lease_ns = hold_lease_ns;
    loop = std::make_unique<head::HeadLoop>(arm, controller, buffer, *server, clock, config);
    server->setControlHandler([this](const link::proto::ControlRequest& r) { return loop->handleControl(r); });
  }

  /// Sends a target until the server holds it: the uplink is asynchronous and, like the XR app
  /// sending every display frame, drops a target while it (re)connects instead of queueing it.
  /// t_robot_ns: the sampling time in the robot clock the XR app would add (0: not known yet);
  /// `from`: another operator app than `client`.
  void sendTarget(const Eigen::Vector3d& position, const link::HeadAngles& angles = {},
                  std::int64_t t_robot_ns = 0, link::LinkClient* from = nullptr) {
    link::LinkClient& sender = from != nullptr ? *from : *client;
    const std::int64_t t = ++operator_t_ns;
    ASSERT_TRUE(eventually([&] {
      sender.sendHeadTarget(target(t, position, angles, t_robot_ns));
      const auto latest = server->latestHeadTarget();
      return latest && latest->t_ns() == t && latest->sender_instance() == sender.instance();
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

  link::proto::ControlReply nominal(link::proto::NominalStepRequest step) {
    link::proto::ControlRequest r;
    r.set_nominal_step(step);
    return request(r);
  }

  Eigen::Isometry3d measuredHead() const {
    return controller.kinematics().forward(arm.trueJoints()) * controller.config().geometry.T_flange_head();
  }
};

TEST(HeadLoop, NominalCaptureThenTargetsMoveTheArm) {
  HeadLoopRig rig(27220);  // 27200 is test_link's endpoints(10): the two run side by side under ctest -j
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
  EXPECT_TRUE(rig.buffer.T_robot_cam(cameras::CameraSide::kLeft, rig.clock.nowNs() - 20'000'000));
}

TEST(HeadLoop, RobotStateReachesTheClientAndControlRequestsAreChecked) {
  HeadLoopRig rig(27210);
  link::proto::ControlRequest mode;
  mode.set_set_visual_mode(link::proto::VISUAL_MODE_ORIENTATION3D);
  EXPECT_TRUE(rig.request(mode).ok());
  mode.set_set_visual_mode(link::proto::VISUAL_MODE_UNSPECIFIED);
  const auto bad_mode = rig.request(mode);
  EXPECT_FALSE(bad_mode.ok());
  EXPECT_NE(bad_mode.error().find("unknown visual mode"), std::string::npos) << bad_mode.error();
  EXPECT_EQ(bad_mode.settings().visual_mode(), link::proto::VISUAL_MODE_ORIENTATION3D);

  link::proto::ControlRequest radius;
  radius.set_set_sphere_radius(0.01);
  EXPECT_FALSE(rig.request(radius).ok());
  radius.set_set_sphere_radius(2.5);
  EXPECT_TRUE(rig.request(radius).ok());
  EXPECT_FALSE(rig.request(link::proto::ControlRequest{}).ok());

  // The scene proxy: nobody chose one at first (each XR app keeps its own); then the session's.
  link::proto::ControlRequest proxy;
  proxy.set_get_settings(true);
  EXPECT_EQ(rig.request(proxy).settings().depth_proxy(), link::proto::DEPTH_PROXY_UNSPECIFIED);
  proxy.set_set_depth_proxy(link::proto::DEPTH_PROXY_UNSPECIFIED);
  const auto bad_proxy = rig.request(proxy);
  EXPECT_FALSE(bad_proxy.ok());
  EXPECT_NE(bad_proxy.error().find("unknown scene proxy"), std::string::npos) << bad_proxy.error();
  proxy.set_set_depth_proxy(link::proto::DEPTH_PROXY_GRID);
  const auto grid = rig.request(proxy);
  EXPECT_TRUE(grid.ok()) << grid.error();
  EXPECT_EQ(grid.settings().depth_proxy(), link::proto::DEPTH_PROXY_GRID);

  // A SUB joins late: keep ticking until a state arrives.
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->sphere_radius() == 2.5;
  }));
  const auto state = *rig.client->latestRobotState();
  EXPECT_EQ(state.visual_mode(), link::proto::VISUAL_MODE_ORIENTATION3D);
  EXPECT_EQ(state.depth_proxy(), link::proto::DEPTH_PROXY_GRID);
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

TEST(HeadLoop, GuidedNominalStepHoldCaptureConfirmAndUndo) {
  HeadLoopRig rig(27270);
  rig.step();
  // 1. Hold: the arm moves the head to T_robot_nom, before any mapping exists.
  auto reply = rig.nominal(link::proto::NOMINAL_REQUEST_HOLD);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.nominal().step(), link::proto::NOMINAL_STEP_HOLDING);
  EXPECT_FALSE(reply.nominal().mapping_set());
  for (int i = 0; i < 500; ++i) rig.step();
  const Eigen::Isometry3d T_robot_nom = rig.controller.config().T_robot_nom;
  EXPECT_LT((rig.measuredHead().translation() - T_robot_nom.translation()).norm(), 0.005);
  EXPECT_FALSE(rig.controller.initialised());

  // 2. Capture: refused without head poses, then refused when they stop arriving.
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_CAPTURE);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("no head pose"), std::string::npos) << reply.error();
  const Eigen::Vector3d head(0.1, 1.6, -0.2);
  const link::HeadAngles looking{10.0 * M_PI / 180, 5.0 * M_PI / 180, -3.0 * M_PI / 180};
  rig.sendTarget(head, looking);
  rig.step();
  for (int i = 0; i < 30; ++i) rig.step();  // 300 ms without a new pose
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_CAPTURE);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("no fresh head pose"), std::string::npos) << reply.error();
  rig.sendTarget(head, looking);
  rig.step();
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_CAPTURE);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.nominal().step(), link::proto::NOMINAL_STEP_CAPTURED);
  EXPECT_NEAR(reply.nominal().yaw_deg(), 10.0, 1e-6);
  EXPECT_NEAR(reply.nominal().pitch_deg(), 5.0, 1e-6);
  EXPECT_NEAR(reply.nominal().roll_deg(), -3.0, 1e-6);
  EXPECT_FALSE(reply.nominal().has_previous());
  // The proposed mapping takes the captured head pose, levelled, to the nominal head pose.
  const Eigen::Isometry3d T_robot_vr = link::fromLinkPose(reply.nominal().t_robot_vr());
  const Eigen::Isometry3d T_robot_head =
      T_robot_vr * link::withoutPitchAndRoll(link::fromLinkPose(reply.nominal().t_vr_hmd_captured())) *
      head::HeadController::T_hmd_head();
  EXPECT_TRUE(T_robot_head.isApprox(T_robot_nom, 1e-9));
  for (int i = 0; i < 20; ++i) rig.step();
  EXPECT_FALSE(rig.controller.initialised());  // nothing applied before confirm
  EXPECT_TRUE(rig.controller.holding());

  // 3. Confirm: the mapping is applied and the head follows again.
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_CONFIRM);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.nominal().step(), link::proto::NOMINAL_STEP_FOLLOWING);
  ASSERT_TRUE(rig.controller.initialised());
  EXPECT_TRUE(rig.controller.T_robot_vr().isApprox(T_robot_vr, 1e-12));
  EXPECT_FALSE(rig.controller.holding());
  EXPECT_FALSE(reply.nominal().has_previous());  // the first mapping: nothing to undo to
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_UNDO);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("nothing to undo"), std::string::npos);

  // A second nominal pose, then undo back to the first.
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_HOLD).ok());
  rig.sendTarget(head + Eigen::Vector3d(0.3, 0, 0), {-0.4, 0, 0});
  rig.step();
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_CAPTURE).ok());
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_CONFIRM);
  ASSERT_TRUE(reply.ok());
  EXPECT_TRUE(reply.nominal().has_previous());
  EXPECT_FALSE(rig.controller.T_robot_vr().isApprox(T_robot_vr, 1e-6));
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_UNDO);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_TRUE(rig.controller.T_robot_vr().isApprox(T_robot_vr, 1e-12));
  EXPECT_FALSE(reply.nominal().has_previous());

  // Undo during a hold drops the capture and follows with the mapping in force.
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_HOLD).ok());
  rig.sendTarget(head, {1.0, 0, 0});
  rig.step();
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_CAPTURE).ok());
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_UNDO).ok());
  EXPECT_TRUE(rig.controller.T_robot_vr().isApprox(T_robot_vr, 1e-12));
  EXPECT_EQ(rig.loop->nominalStep(), link::proto::NOMINAL_STEP_FOLLOWING);
  EXPECT_FALSE(rig.nominal(link::proto::NOMINAL_REQUEST_CONFIRM).ok());  // nothing captured
}

TEST(HeadLoop, ACalibrationHeadPoseIsHeldWithTheOperatorIgnoredUntilReleased) {
  HeadLoopRig rig(27320, 600'000'000'000);  // a lease longer than the test (leases: their own test)
  rig.step();
  auto pose = [](const Eigen::Isometry3d& T_robot_head, bool release = false) {
    link::proto::ControlRequest r;
    r.mutable_calibration_head_pose()->set_holder("test wizard");
    if (release) {
      r.mutable_calibration_head_pose()->set_release(true);
    } else {
      link::toLinkPose(T_robot_head, r.mutable_calibration_head_pose()->mutable_t_robot_head());
    }
    return r;
  };
  const Eigen::Isometry3d T_robot_nom = rig.controller.config().T_robot_nom;
  // The head turned 50° left and 30° down, 5 cm to the side: the wizard's kind of pose.
  Eigen::Isometry3d T_robot_head = T_robot_nom;
  T_robot_head.linear() = T_robot_nom.linear() * Eigen::AngleAxisd(50 * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix() *
                          Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitY()).matrix();
  T_robot_head.translation() += Eigen::Vector3d(0, 0.05, 0);

  // Refused: no pose, a pose outside the workspace, and during the nominal-pose step.
  link::proto::ControlRequest empty;
  empty.mutable_calibration_head_pose()->set_holder("test wizard");
  auto reply = rig.request(empty);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("no pose"), std::string::npos) << reply.error();
  Eigen::Isometry3d far = T_robot_head;
  far.translation().x() += 1.0;
  reply = rig.request(pose(far));
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("outside the head workspace"), std::string::npos) << reply.error();
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_HOLD).ok());
  reply = rig.request(pose(T_robot_head));
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("nominal-pose step"), std::string::npos) << reply.error();
  ASSERT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_UNDO).ok());

  // Held: the head goes there at the approach speeds and stays; the state says so.
  reply = rig.request(pose(T_robot_head));
  ASSERT_TRUE(reply.ok()) << reply.error();
  for (int i = 0; i < 400; ++i) rig.step();
  auto measured = rig.measuredHead();
  EXPECT_LT((measured.translation() - T_robot_head.translation()).norm(), 0.002);
  EXPECT_LT(Eigen::AngleAxisd(measured.linear().transpose() * T_robot_head.linear()).angle() * 180 / M_PI, 0.5);
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->calibration_hold();
  }));
  const Eigen::Isometry3d reported = link::fromLinkPose(rig.client->latestRobotState()->t_robot_head());
  EXPECT_LT((reported.translation() - T_robot_head.translation()).norm(), 0.002);
  // The nominal step cannot start meanwhile, and operator targets do not move the head.
  reply = rig.nominal(link::proto::NOMINAL_REQUEST_HOLD);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("held for calibration"), std::string::npos) << reply.error();
  rig.sendTarget(Eigen::Vector3d(0.2, 1.6, 0.1), {0.5, 0, 0});
  for (int i = 0; i < 100; ++i) rig.step();
  EXPECT_TRUE(rig.measuredHead().isApprox(measured, 1e-3));

  // Released: no longer held (the state says so), the nominal step may run again.
  ASSERT_TRUE(rig.request(pose({}, true)).ok());
  EXPECT_FALSE(rig.controller.holding());
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && !s->calibration_hold();
  }));
  EXPECT_TRUE(rig.nominal(link::proto::NOMINAL_REQUEST_HOLD).ok());
}

// A calibration pose is refused only when the arm cannot get there the way the hold takes it (the
// head stepped towards the pose, each IK seeded with the last), not when one IK from where the arm
// stands stops short: from the rig's start, 45 of 3689 wizard-like poses (yaw ±150°, pitch ±80°,
// roll ±45° about the nominal pose) were refused so, none the other way round. One CI run of
// console_calibrate_test lost four rim views to such refusals and missed a polar bin.
TEST(HeadLoop, ACalibrationPoseTheArmReachesAlongItsApproachIsHeldThoughOneIkFromWhereItStandsStopsShort) {
  HeadLoopRig rig(28340, 600'000'000'000);
  rig.step();
  const Eigen::Isometry3d T_robot_nom = rig.controller.config().T_robot_nom;
  Eigen::Isometry3d T_robot_head = T_robot_nom;  // turned 80° right and 50° up
  T_robot_head.linear() = T_robot_nom.linear() * Eigen::AngleAxisd(-80 * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix() *
                          Eigen::AngleAxisd(-50 * M_PI / 180, Eigen::Vector3d::UnitY()).matrix();
  const Eigen::Isometry3d T_head_flange = rig.controller.config().geometry.T_flange_head().inverse();
  ASSERT_FALSE(rig.controller.kinematics()
                   .inverse(T_robot_head * T_head_flange, rig.arm.trueJoints(), rig.controller.config().ik)
                   .converged())
      << "the case needs a pose one IK from the start does not reach";
  link::proto::ControlRequest r;
  r.mutable_calibration_head_pose()->set_holder("test wizard");
  link::toLinkPose(T_robot_head, r.mutable_calibration_head_pose()->mutable_t_robot_head());
  const auto reply = rig.request(r);
  ASSERT_TRUE(reply.ok()) << reply.error();
  for (int i = 0; i < 600; ++i) rig.step();  // 92° at the approach's 45°/s, and the filter
  const Eigen::Isometry3d measured = rig.measuredHead();
  EXPECT_LT((measured.translation() - T_robot_head.translation()).norm(), 0.002);
  EXPECT_LT(Eigen::AngleAxisd(measured.linear().transpose() * T_robot_head.linear()).angle() * 180 / M_PI, 0.5);
}

// Hand-eye sample collection: the head moves along the sinusoidal pattern about the nominal pose,
// turning about all three axes, and follows the pattern's pose within the arm's lag.
TEST(HeadLoop, TheCalibrationPatternTurnsTheHeadAboutThreeAxes) {
  HeadLoopRig rig(27330, 600'000'000'000);  // a lease longer than the test (leases: their own test)
  rig.step();
  link::proto::ControlRequest r;
  r.mutable_calibration_head_pose()->set_holder("test wizard");
  r.mutable_calibration_head_pose()->set_pattern_amplitude_deg(45.0);
  auto reply = rig.request(r);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("outside [0, 30]"), std::string::npos) << reply.error();
  r.mutable_calibration_head_pose()->set_pattern_amplitude_deg(20.0);  // no pose: about the nominal one
  const std::int64_t start_ns = rig.clock.nowNs();
  reply = rig.request(r);
  ASSERT_TRUE(reply.ok()) << reply.error();
  const Eigen::Isometry3d T_robot_nom = rig.controller.config().T_robot_nom;
  for (int i = 0; i < 500; ++i) rig.step();  // reach the centre and let the amplitude ramp up
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  double worst_lag_deg = 0, worst_position_m = 0;
  for (int i = 0; i < 1200; ++i) {  // 12 s: more than a yaw and a pitch period
    rig.step();
    const Eigen::Isometry3d measured = rig.measuredHead();
    // Yaw, pitch, roll of the head relative to the centre (z, y, x).
    const Eigen::Matrix3d R = T_robot_nom.linear().transpose() * measured.linear();
    const Eigen::Vector3d ypr =
        Eigen::Vector3d(std::atan2(R(1, 0), R(0, 0)), std::asin(-R(2, 0)), std::atan2(R(2, 1), R(2, 2))) * 180 / M_PI;
    lo = lo.cwiseMin(ypr);
    hi = hi.cwiseMax(ypr);
    worst_position_m = std::max(worst_position_m, (measured.translation() - T_robot_nom.translation()).norm());
    const Eigen::Isometry3d wanted = head::calibrationPatternPose(T_robot_nom, 20.0, rig.clock.nowNs() - start_ns);
    worst_lag_deg = std::max(worst_lag_deg,
                             Eigen::AngleAxisd(measured.linear().transpose() * wanted.linear()).angle() * 180 / M_PI);
  }
  EXPECT_GT(hi[0] - lo[0], 30.0) << "yaw " << lo[0] << ".." << hi[0];
  EXPECT_GT(hi[1] - lo[1], 14.0) << "pitch " << lo[1] << ".." << hi[1];
  EXPECT_GT(hi[2] - lo[2], 5.0) << "roll " << lo[2] << ".." << hi[2];
  // The arm's dead time (118 ms) at the pattern's fastest turn (≈ 21°/s) and the filter; the
  // head's centre moves only by the lag's lever arm.
  EXPECT_LT(worst_lag_deg, 5.0);
  EXPECT_LT(worst_position_m, 0.01);
  std::printf("pattern: yaw %.1f..%.1f°, pitch %.1f..%.1f°, roll %.1f..%.1f°, lag ≤ %.2f°, centre ≤ %.1f mm\n", lo[0],
              hi[0], lo[1], hi[1], lo[2], hi[2], worst_lag_deg, worst_position_m * 1e3);
  ASSERT_TRUE(rig.request([] {
                link::proto::ControlRequest release;
                release.mutable_calibration_head_pose()->set_release(true);
                return release;
              }())
                  .ok());
  EXPECT_FALSE(rig.controller.holding());
}

// A calibration hold is a lease: renewed it stands, silent for a lease it ends by itself (and says
// why); another holder is refused with the name of the one holding; the console's release ends
// any hold, a holder's late release only its own. The lease clock stands while the robot serves
// a control request (and for a lease after it), so the robot's own silence is not the holder's.
TEST(HeadLoop, ACalibrationHoldIsALeaseThatEndsWhenItsHolderFallsSilent) {
  HeadLoopRig rig(28290);  // the default lease: 2 s
  rig.step();
  const auto holdRequest = [](const std::string& holder, std::uint64_t lease = 0) {
    link::proto::ControlRequest r;
    r.mutable_calibration_head_pose()->set_holder(holder);
    r.mutable_calibration_head_pose()->set_lease(lease);
    r.mutable_calibration_head_pose()->set_pattern_amplitude_deg(5.0);
    return r;
  };
  const auto renew = [](std::uint64_t lease) {
    link::proto::ControlRequest r;
    r.mutable_calibration_head_pose()->set_renew(true);
    r.mutable_calibration_head_pose()->set_lease(lease);
    return r;
  };
  const auto seconds = [&](double s) {
    for (int i = 0; i < int(std::lround(s * 100)); ++i) rig.step();
  };

  link::proto::ControlRequest nameless = holdRequest("");
  auto reply = rig.request(nameless);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("needs a holder"), std::string::npos) << reply.error();

  reply = rig.request(holdRequest("wizard A"));
  ASSERT_TRUE(reply.ok()) << reply.error();
  const std::uint64_t lease = reply.hold().lease();
  EXPECT_GT(lease, 0u);
  EXPECT_EQ(reply.hold().holder(), "wizard A");
  EXPECT_DOUBLE_EQ(reply.hold().lease_s(), 2.0);
  // Another holder is refused with the name of the one holding.
  reply = rig.request(holdRequest("wizard B"));
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("held for calibration by wizard A"), std::string::npos) << reply.error();
  // Renewed every second, it stands for 6 s; the state names its holder.
  for (int k = 0; k < 6; ++k) {
    seconds(1.0);
    ASSERT_TRUE(rig.request(renew(lease)).ok()) << k;
  }
  EXPECT_TRUE(rig.controller.holding());
  EXPECT_EQ(rig.loop->hold().holder(), "wizard A");
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->hold().lease() == lease && s->hold().holder() == "wizard A" && s->calibration_hold();
  }));
  // Silent: still held at 1.9 s, released by 2.1 s, and the reason is kept.
  const std::int64_t silent_from = rig.clock.nowNs();
  seconds(1.9);
  EXPECT_TRUE(rig.controller.holding());
  seconds(0.2);
  EXPECT_FALSE(rig.controller.holding());
  EXPECT_EQ(rig.loop->hold().lease(), 0u);
  EXPECT_NE(rig.loop->hold().last_release().find("wizard A's hold (lease " + std::to_string(lease) +
                                                 ") released: not renewed for 2.0 s"),
            std::string::npos)
      << rig.loop->hold().last_release();
  EXPECT_LE(rig.clock.nowNs() - silent_from, 2'100'000'000);
  // Its late renewal is refused with what happened; it never becomes a hold again.
  reply = rig.request(renew(lease));
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("not renewed"), std::string::npos) << reply.error();
  reply = rig.request(holdRequest("wizard A", lease));
  EXPECT_FALSE(reply.ok());
  EXPECT_FALSE(rig.controller.holding());

  // While the robot serves a request (a long still), the lease clock stands, and a full lease
  // follows it.
  reply = rig.request(holdRequest("wizard B"));
  ASSERT_TRUE(reply.ok()) << reply.error();
  const std::uint64_t lease_b = reply.hold().lease();
  EXPECT_NE(lease_b, lease);
  rig.loop->controlStarted();
  seconds(5.0);
  rig.loop->controlFinished();
  EXPECT_TRUE(rig.controller.holding());
  seconds(1.9);
  EXPECT_TRUE(rig.controller.holding());
  // A stale holder's release does not end B's hold; the console's (no lease) does.
  link::proto::ControlRequest stale_release;
  stale_release.mutable_calibration_head_pose()->set_release(true);
  stale_release.mutable_calibration_head_pose()->set_lease(lease);
  EXPECT_TRUE(rig.request(stale_release).ok());
  EXPECT_TRUE(rig.controller.holding());
  link::proto::ControlRequest console_release;
  console_release.mutable_calibration_head_pose()->set_release(true);
  console_release.mutable_calibration_head_pose()->set_holder("the console (supervisor)");
  EXPECT_TRUE(rig.request(console_release).ok());
  EXPECT_FALSE(rig.controller.holding());
  EXPECT_NE(rig.loop->hold().last_release().find("released by the console (supervisor)"), std::string::npos)
      << rig.loop->hold().last_release();
}

TEST(HeadLoop, KnobsArmStopAndClearThroughControlRequests) {
  HeadLoopRig rig(27280);
  rig.step();
  link::proto::ControlRequest r;
  r.set_set_filter_cutoff_hz(20.0);
  auto reply = rig.request(r);
  EXPECT_TRUE(reply.ok());
  EXPECT_DOUBLE_EQ(reply.settings().filter_cutoff_hz(), 20.0);
  EXPECT_DOUBLE_EQ(rig.controller.config().cutoff_hz, 20.0);
  r.set_set_filter_cutoff_hz(std::numeric_limits<double>::infinity());  // off
  EXPECT_TRUE(rig.request(r).ok());
  for (double bad : {0.0, -3.0, std::nan("")}) {
    r.set_set_filter_cutoff_hz(bad);
    reply = rig.request(r);
    EXPECT_FALSE(reply.ok()) << bad;
    EXPECT_TRUE(std::isinf(reply.settings().filter_cutoff_hz()));
  }
  r.mutable_set_jump_threshold()->set_position_m(0.05);
  r.mutable_set_jump_threshold()->set_angle_deg(30.0);
  reply = rig.request(r);
  EXPECT_TRUE(reply.ok());
  EXPECT_DOUBLE_EQ(rig.controller.config().jump_position, 0.05);
  EXPECT_NEAR(rig.controller.config().jump_angle, 30.0 * M_PI / 180, 1e-12);
  EXPECT_NEAR(reply.settings().jump_angle_deg(), 30.0, 1e-9);
  r.mutable_set_jump_threshold()->set_angle_deg(0.0);
  EXPECT_FALSE(rig.request(r).ok());
  r.set_set_jpeg_quality(50);  // not the head loop's: RobotControl routes it to the video path
  EXPECT_FALSE(rig.request(r).ok());

  r.set_arm_stop(true);
  EXPECT_TRUE(rig.request(r).ok());
  EXPECT_EQ(rig.arm.status(), arm::ArmStatus::kStopped);
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && !s->arm_ok();
  }));
  EXPECT_EQ(rig.client->latestRobotState()->fault(), "arm stopped from the console");
  link::proto::RobotHealth health;
  rig.loop->fillHealth(&health);
  EXPECT_FALSE(health.arm_ok());
  // Clear fault is answered at once; the recovery runs on its own thread and the state says how
  // it went.
  r.set_clear_fault(true);
  reply = rig.request(r);
  EXPECT_TRUE(reply.ok());
  EXPECT_TRUE(reply.pending());
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->arm_ok();
  }));
  EXPECT_EQ(rig.arm.status(), arm::ArmStatus::kOk);
  EXPECT_EQ(rig.client->latestRobotState()->fault(), "");
  // Nothing to clear: ok, nothing pending.
  reply = rig.request(r);
  EXPECT_TRUE(reply.ok());
  EXPECT_FALSE(reply.pending());
  // A simulated arm's dropped connection does not come back on "clear fault": the state says so.
  rig.arm.dropConnection();
  reply = rig.request(r);
  EXPECT_TRUE(reply.pending());
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && !s->arm_ok() && s->fault().find("disconnected") != std::string::npos;
  })) << (rig.client->latestRobotState() ? rig.client->latestRobotState()->fault() : std::string("no state"));
}

TEST(HeadLoop, TheStudysTrialIndicatorIsRelayedWithItsElapsedTimeAdvanced) {
  HeadLoopRig rig(27310);
  rig.step();
  link::proto::ControlRequest r;
  r.mutable_set_trial_indicator()->set_running(true);
  r.mutable_set_trial_indicator()->set_elapsed_s(12.5);
  r.mutable_set_trial_indicator()->set_time_limit_s(300.0);
  ASSERT_TRUE(rig.request(r).ok());
  for (int i = 0; i < 150; ++i) rig.step();  // 1.5 s of robot time
  ASSERT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && s->trial().running() && s->trial().elapsed_s() > 13.9;
  }));
  const auto state = *rig.client->latestRobotState();
  EXPECT_NEAR(state.trial().elapsed_s(), 12.5 + 1.5, 0.5);  // advanced by the robot clock
  EXPECT_DOUBLE_EQ(state.trial().time_limit_s(), 300.0);
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    r.mutable_set_trial_indicator()->set_elapsed_s(bad);
    EXPECT_FALSE(rig.request(r).ok()) << bad;
  }
  r.mutable_set_trial_indicator()->Clear();  // the trial ended
  ASSERT_TRUE(rig.request(r).ok());
  EXPECT_TRUE(eventually([&] {
    rig.step();
    const auto s = rig.client->latestRobotState();
    return s && !s->has_trial();
  }));
}

TEST(HeadLoop, EveryTickIsTelemetryInNumberedBatches) {
  HeadLoopRig rig(27290);
  link::proto::ControlRequest capture;
  capture.set_capture_nominal(true);
  rig.sendTarget({0, 1.6, 0});
  rig.step();
  ASSERT_TRUE(rig.request(capture).ok());
  // Keep ticking until the client has heard batches (a SUB joins late), then count exactly.
  ASSERT_TRUE(eventually([&] {
    rig.sendTarget({0, 1.6, 0});
    rig.step();
    return !rig.client->takeTelemetry().empty();
  }));
  const std::int64_t first_tick = rig.loop->ticks();
  for (int i = 0; i < 100; ++i) {
    rig.sendTarget({0.001 * i, 1.6, 0});
    rig.step();
  }
  std::vector<link::proto::HeadTick> ticks;
  std::uint64_t last_batch = 0;
  ASSERT_TRUE(eventually([&] {
    for (const auto& e : rig.client->takeTelemetry()) {
      if (!e.has_robot_telemetry()) {
        ADD_FAILURE() << "not robot telemetry";
        continue;
      }
      if (last_batch) {
        EXPECT_EQ(e.robot_telemetry().batch(), last_batch + 1);
      }
      last_batch = e.robot_telemetry().batch();
      for (const auto& t : e.robot_telemetry().ticks()) ticks.push_back(t);
    }
    return !ticks.empty() && ticks.back().t_ns() >= rig.clock.nowNs() - 50'000'000;
  }));
  // Every tick since, in order, each with the target it acted on and the measured head.
  std::size_t sent = 0;
  for (std::size_t i = 1; i < ticks.size(); ++i) EXPECT_EQ(ticks[i].t_ns() - ticks[i - 1].t_ns(), 10'000'000);
  for (const auto& t : ticks) {
    sent += t.outcome() == link::proto::HEAD_TICK_SENT;
    EXPECT_TRUE(t.target_new());
    EXPECT_EQ(t.target_arrival_ns(), t.t_ns());
    EXPECT_TRUE(t.has_t_robot_head_measured());
    EXPECT_GT(t.joint_state_ns(), 0);
  }
  EXPECT_GE(ticks.size(), std::size_t(rig.loop->ticks() - first_tick - 5));
  EXPECT_EQ(sent, ticks.size());
}

}  // namespace
}  // namespace telesphere::robot

namespace telesphere::robot {
namespace {

TEST(HeadLoop, TargetsAreTimedInTheRobotClockAndOrderedPerSender) {
  HeadLoopRig rig(27510);
  const Eigen::Vector3d head(0.0, 1.6, 0.0);
  // An operator PC whose steady clock is far ahead of the robot's; its targets carry their
  // sampling time in the robot clock, as the XR app adds it once its pings have an offset.
  rig.operator_t_ns = 5'000'000'000'000;
  rig.sendTarget(head, {}, rig.clock.nowNs());
  rig.step();
  link::proto::ControlRequest capture;
  capture.set_capture_nominal(true);
  ASSERT_TRUE(rig.request(capture).ok());
  for (int i = 0; i < 50; ++i) {
    rig.sendTarget(head, {}, rig.clock.nowNs());
    rig.step();
  }
  ASSERT_TRUE(rig.controller.initialised());
  EXPECT_EQ(rig.controller.rejectionCount(head::HeadRejectReason::kStale), 0);
  EXPECT_EQ(rig.loop->targetsStampedOnArrival(), 0);
  const std::int64_t sent = rig.loop->targetsSent();
  EXPECT_GT(sent, 40);

  // A pose sampled 300 ms ago that the uplink held back: stale on its own stamp, not followed
  // (stamped on arrival it would look fresh).
  rig.sendTarget(head + Eigen::Vector3d(0.05, 0, 0), {}, rig.clock.nowNs() - 300'000'000);
  rig.step();
  EXPECT_EQ(rig.controller.rejectionCount(head::HeadRejectReason::kStale), 1);

  // A pose stamped 50 ms in the robot's future (a wrong clock offset): refused too.
  rig.sendTarget(head, {}, rig.clock.nowNs() + 50'000'000);
  rig.step();
  EXPECT_EQ(rig.controller.rejectionCount(head::HeadRejectReason::kFromFuture), 1);

  // The operator PC restarts: a new sender whose clock starts near zero is heard at once.
  link::LinkClient restarted(rig.endpoints);
  rig.operator_t_ns = 10;
  for (int i = 0; i < 5; ++i) {
    rig.sendTarget(head + Eigen::Vector3d(0.01, 0, 0), {}, rig.clock.nowNs(), &restarted);
    rig.step();
  }
  EXPECT_EQ(rig.server->latestHeadTarget()->sender_instance(), restarted.instance());
  EXPECT_GE(rig.loop->targetsSent(), sent + 5);
  EXPECT_EQ(rig.controller.rejectionCount(head::HeadRejectReason::kOutOfOrder), 0);

  // A sender without a clock offset yet: its targets are stamped on arrival, and counted.
  rig.sendTarget(head, {}, 0, &restarted);
  rig.step();
  EXPECT_EQ(rig.loop->targetsStampedOnArrival(), 1);
}

}  // namespace
}  // namespace telesphere::robot
