// SPDX-License-Identifier: MIT
/// @brief The simulated manipulator with the wrist marker (robot/stereo/simulated_manipulator.h): home
///        configuration at the marker's place, reports at 100 Hz that interpolate to the true
///        path, a path that keeps the marker facing the head and turns the wrist about several
///        axes (what hand-eye calibration needs), and a clear refusal for a mount out of reach.
#include <gtest/gtest.h>

#include "calib/hand_eye_calibration.h"
#include "robot/stereo/simulated_manipulator.h"
#include "robot/cameras/synthetic_scene.h"

namespace telesphere::robot {
namespace {

stereo::SimulatedManipulator makeExample() {
  std::string error;
  auto m = stereo::SimulatedManipulator::create({}, &error);
  EXPECT_TRUE(m) << error;
  return *m;
}

TEST(SimulatedManipulator, HomeIsTheMarkersPlaceAndReportsFollowThePath) {
  stereo::SimulatedManipulator m = makeExample();
  const arm::Xarm6Kinematics kinematics;
  const stereo::ManipulatorMounting& mount = m.config().mounting;
  const Eigen::Isometry3d T_home = mount.T_robot_mount * kinematics.forward(m.qHome()) * mount.T_wrist_marker;
  EXPECT_LT((T_home.translation() - cameras::DefaultSceneLayout::T_robot_marker_centre().translation()).norm(), 1e-5);
  const Eigen::Vector3d to_head = (cameras::DefaultSceneLayout{}.head_position - T_home.translation()).normalized();
  EXPECT_GT(to_head.dot(T_home.linear().col(2)), std::cos(1e-4));  // facing the head

  head::JointStateBuffer reports{head::HeadGeometry{}};
  const std::int64_t t0 = 1'000'003'000;
  m.update(t0, reports);
  EXPECT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports.window()->first, 1'000'000'000);  // on the report period's grid
  m.update(t0 + 95'000'000, reports);
  EXPECT_EQ(reports.size(), 10u);
  m.update(t0 + 95'000'000, reports);  // nothing new is due
  EXPECT_EQ(reports.size(), 10u);
  // Between reports the interpolated joints and FK are within encoder noise and the chord error
  // of the path (≤ 0.35 rad · (2π/7 s)² · (10 ms)² / 8 ≈ 4e-6 rad).
  for (std::int64_t t = t0; t < t0 + 90'000'000; t += 3'300'000) {
    const auto q = reports.jointsAt(t);
    ASSERT_TRUE(q);
    EXPECT_LT((*q - m.q(t)).cwiseAbs().maxCoeff(), 1.5e-4) << t;
    EXPECT_LT((reports.T_robot_flange(t)->translation() - m.T_mount_wrist(t).translation()).norm(), 2e-4);
  }
}

TEST(SimulatedManipulator, ThePathKeepsTheMarkerFacingTheHeadAndTurnsTheWrist) {
  stereo::SimulatedManipulator m = makeExample();
  const cameras::DefaultSceneLayout layout;
  std::vector<calib::HandEyeSample> samples;
  double worst_facing_deg = 0, farthest_m = 0;
  for (std::int64_t t = 0; t < 120'000'000'000; t += 2'000'000'000) {
    const Eigen::Isometry3d T = m.T_robot_marker(t);
    const Eigen::Vector3d to_head = (layout.head_position - T.translation()).normalized();
    worst_facing_deg = std::max(worst_facing_deg, std::acos(std::clamp(to_head.dot(T.linear().col(2)), -1.0, 1.0)) * 180 / M_PI);
    farthest_m = std::max(farthest_m, (T.translation() - cameras::DefaultSceneLayout::T_robot_marker_centre().translation()).norm());
    calib::HandEyeSample s;
    s.T_mount_wrist = m.T_mount_wrist(t);
    s.T_robot_flange.linear() = Eigen::AngleAxisd(0.01 * double(samples.size()), Eigen::Vector3d(1, 2, 3).normalized())
                                    .toRotationMatrix() *
                                Eigen::AngleAxisd(0.2 * std::sin(double(samples.size())), Eigen::Vector3d::UnitZ())
                                    .toRotationMatrix();
    s.corners_l.emplace();
    samples.push_back(s);
  }
  EXPECT_LT(worst_facing_deg, 35.0);  // ArUco detection works to beyond 60°
  EXPECT_GT(worst_facing_deg, 10.0);  // and the marker does turn
  EXPECT_LT(farthest_m, 0.20);        // it stays in the middle of the view
  const auto identifiability = calib::checkHandEyeIdentifiability(samples);
  EXPECT_GT(identifiability.wrist_axis_spread_deg, 15.0);
}

TEST(SimulatedManipulator, AMountOutOfReachIsRefusedWithTheReason) {
  stereo::SimulatedManipulatorConfig config;
  config.mounting.T_robot_mount.translation() = Eigen::Vector3d(4.0, 0.35, 0.10);  // 3 m from the marker
  std::string error;
  EXPECT_FALSE(stereo::SimulatedManipulator::create(config, &error));
  EXPECT_NE(error.find("cannot reach the marker's place"), std::string::npos) << error;
  config = {};
  config.period_s[2] = 0.0;
  EXPECT_FALSE(stereo::SimulatedManipulator::create(config, &error));
  EXPECT_NE(error.find("periods positive"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::robot
