// SPDX-License-Identifier: MIT
/// @brief The console's small state machines on a simulated clock: whether a peer is waiting,
///        connected, silent or gone (and since when); faults that stay until acknowledged; the
///        nominal-pose gate (fresh and still head poses only).
#include <gtest/gtest.h>

#include "console/supervision/connection_monitor.h"
#include "console/supervision/fault_log.h"
#include "console/supervision/nominal_pose_gate.h"

namespace telesphere::console::supervision {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;

TEST(PeerMonitor, WaitingConnectedSilentGoneAndBack) {
  PeerMonitor m(0, PeerThresholds{1 * kSecond, 5 * kSecond});
  EXPECT_EQ(m.update(0, 3 * kSecond), PeerState::kWaiting);
  EXPECT_NEAR(m.seconds(), 3.0, 1e-9);
  EXPECT_EQ(m.update(4 * kSecond, 4 * kSecond), PeerState::kConnected);
  EXPECT_EQ(m.update(9 * kSecond + kSecond / 2, 10 * kSecond), PeerState::kConnected);
  EXPECT_NEAR(m.seconds(), 6.0, 1e-9);  // connected since 4 s
  EXPECT_EQ(m.update(9 * kSecond, 10 * kSecond), PeerState::kSilent);  // quiet for 1 s
  EXPECT_EQ(m.update(9 * kSecond, 11 * kSecond), PeerState::kSilent);
  EXPECT_NEAR(m.seconds(), 2.0, 1e-9);  // silent since it was last heard
  EXPECT_EQ(m.update(9 * kSecond, 15 * kSecond), PeerState::kGone);
  EXPECT_NEAR(m.seconds(), 6.0, 1e-9);
  EXPECT_EQ(m.describe(), "gone for 6.0 s");
  EXPECT_EQ(m.reconnects(), 0);
  EXPECT_EQ(m.update(20 * kSecond, 20 * kSecond), PeerState::kConnected);
  EXPECT_EQ(m.reconnects(), 1);
  // Heard once long ago before the console looked: still waiting, not "gone" at start.
  PeerMonitor late(10 * kSecond, PeerThresholds{1 * kSecond, 5 * kSecond});
  EXPECT_EQ(late.update(1 * kSecond, 10 * kSecond), PeerState::kWaiting);
}

TEST(PeerMonitor, FormatsDurations) {
  EXPECT_EQ(formatDuration(4.24), "4.2 s");
  EXPECT_EQ(formatDuration(185), "3 min 05 s");
  EXPECT_EQ(formatDuration(7800), "2 h 10 min");
  EXPECT_EQ(formatDuration(-1), "0.0 s");
}

TEST(FaultLog, StaysUntilAcknowledgedAndDoesNotNag) {
  FaultLog log;
  log.raise("arm", "arm: stopped", 1);
  log.raise("arm", "arm: stopped", 2);  // still the same fault
  ASSERT_EQ(log.unacknowledged().size(), 1u);
  log.clear("arm", 3);
  ASSERT_EQ(log.unacknowledged().size(), 1u);  // cleared, but not yet seen
  EXPECT_EQ(log.unacknowledged()[0].cleared_ns, 3);
  log.raise("arm", "arm: stopped again", 4);  // back before anyone looked
  ASSERT_EQ(log.unacknowledged().size(), 1u);
  EXPECT_EQ(log.unacknowledged()[0].times, 2);
  EXPECT_EQ(log.unacknowledged()[0].cleared_ns, 0);
  EXPECT_EQ(log.unacknowledged()[0].text, "arm: stopped again");
  const auto version = log.version();
  log.acknowledgeAll();
  EXPECT_GT(log.version(), version);
  EXPECT_TRUE(log.unacknowledged().empty());
  log.raise("arm", "arm: stopped again", 5);  // still holds: acknowledged, no nagging
  EXPECT_TRUE(log.unacknowledged().empty());
  log.clear("arm", 6);
  log.raise("arm", "arm: a new stop", 7);  // cleared and back: a new fault
  ASSERT_EQ(log.unacknowledged().size(), 1u);
  EXPECT_EQ(log.unacknowledged()[0].first_ns, 7);
  EXPECT_EQ(log.history().size(), 2u);
  // One-off events.
  log.raise("robot.restart", "the robot restarted", 8);
  log.clear("robot.restart", 8);
  EXPECT_EQ(log.unacknowledged().size(), 2u);
}

std::deque<telemetry::HeadPoseSample> poses(double t_end, int n, double dt, double turn_deg_per_s, double yaw_deg) {
  std::deque<telemetry::HeadPoseSample> out;
  for (int i = 0; i < n; ++i) {
    const double t = t_end - (n - 1 - i) * dt;
    telemetry::HeadPoseSample p;
    p.t = t;
    p.T_vr_hmd.linear() = link::headRotationOf({(yaw_deg + turn_deg_per_s * t) * M_PI / 180, 0.1, -0.05});
    p.T_vr_hmd.translation() << 0.1, 1.6, 0.2;
    out.push_back(p);
  }
  return out;
}

TEST(NominalPoseGate, OnlyFreshAndStillPosesMayBeCaptured) {
  EXPECT_FALSE(evaluateNominalGate({}, 10.0).can_capture);
  EXPECT_NE(evaluateNominalGate({}, 10.0).reason.find("no head pose"), std::string::npos);

  const auto still = poses(10.0, 50, 0.011, 0.0, 12.0);
  const NominalGateStatus ok = evaluateNominalGate(still, 10.05);
  EXPECT_TRUE(ok.can_capture) << ok.reason;
  ASSERT_TRUE(ok.angles);
  EXPECT_NEAR(ok.angles->yaw * 180 / M_PI, 12.0, 1e-9);
  EXPECT_NEAR(ok.angles->pitch, 0.1, 1e-9);
  EXPECT_NEAR(ok.angles->roll, -0.05, 1e-9);

  const NominalGateStatus stale = evaluateNominalGate(still, 11.0);
  EXPECT_FALSE(stale.can_capture);
  EXPECT_NE(stale.reason.find("stale"), std::string::npos) << stale.reason;

  const NominalGateStatus turning = evaluateNominalGate(poses(10.0, 50, 0.011, 10.0, 0.0), 10.01);
  EXPECT_FALSE(turning.can_capture);
  EXPECT_NEAR(turning.turn_deg, 5.0, 0.2);  // 10°/s over the 0.5 s window
  EXPECT_NE(turning.reason.find("moving"), std::string::npos) << turning.reason;

  const NominalGateStatus few = evaluateNominalGate(poses(10.0, 3, 0.011, 0.0, 0.0), 10.0);
  EXPECT_FALSE(few.can_capture);
}

}  // namespace
}  // namespace telesphere::console::supervision
