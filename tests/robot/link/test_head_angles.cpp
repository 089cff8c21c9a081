// SPDX-License-Identifier: MIT
/// @brief Head yaw, pitch and roll: round trips over the whole range (seeded), the sign
///        conventions on hand-made poses, the straight-up/down cases, and removing pitch and roll.
#include <gtest/gtest.h>

#include <random>

#include "robot/link/head_angles.h"

namespace telesphere::link {
namespace {

TEST(HeadAngles, SignsOnHandMadePoses) {
  // Turning left: the gaze (−z) swings towards −x.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_NEAR(headAnglesOf(T).yaw, 0.3, 1e-12);
  EXPECT_LT((T.linear() * Eigen::Vector3d(0, 0, -1)).x(), 0);
  // Looking up: rotation about the view's +x lifts −z.
  T.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(headAnglesOf(T).pitch, 0.2, 1e-12);
  EXPECT_GT((T.linear() * Eigen::Vector3d(0, 0, -1)).y(), 0);
  // Right ear down: the top of the head leans to +x.
  T.linear() = Eigen::AngleAxisd(-0.25, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(headAnglesOf(T).roll, 0.25, 1e-12);
  EXPECT_GT((T.linear() * Eigen::Vector3d(0, 1, 0)).x(), 0);
}

TEST(HeadAngles, RoundTripsOverTheRange) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> yaw(-M_PI + 1e-6, M_PI - 1e-6), pitch(-M_PI / 2 + 1e-3, M_PI / 2 - 1e-3),
      roll(-M_PI + 1e-6, M_PI - 1e-6);
  for (int i = 0; i < 20000; ++i) {
    const HeadAngles a{yaw(rng), pitch(rng), roll(rng)};
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = headRotationOf(a);
    const HeadAngles b = headAnglesOf(T);
    EXPECT_NEAR(b.yaw, a.yaw, 1e-6) << i;
    EXPECT_NEAR(b.pitch, a.pitch, 1e-9) << i;
    EXPECT_NEAR(b.roll, a.roll, 1e-6) << i;
  }
}

TEST(HeadAngles, StraightUpAndDownKeepAYawFromTheTopOfTheHead) {
  for (const double yaw : {0.0, 0.7, -2.0})
    for (const double pitch : {M_PI / 2, -M_PI / 2}) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = headRotationOf({yaw, pitch, 0.0});
      const HeadAngles a = headAnglesOf(T);
      EXPECT_NEAR(a.pitch, pitch, 1e-6);
      EXPECT_NEAR(a.yaw, yaw, 1e-6) << yaw << " " << pitch;
      EXPECT_TRUE(std::isfinite(a.roll));
    }
}

TEST(HeadAngles, WithoutPitchAndRollKeepsYawAndPositionOnly) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> yaw(-M_PI + 1e-3, M_PI - 1e-3), tilt(-1.4, 1.4);
  for (int i = 0; i < 500; ++i) {
    const double psi = yaw(rng), theta = tilt(rng), phi = tilt(rng);
    Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
    // OpenXR head: yaw about +y, then pitch about +x, then roll about −z (forward).
    T_vr_hmd.linear() = (Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitX()) *
                         Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitZ()))
                            .toRotationMatrix();
    T_vr_hmd.translation() << 0.3, 1.7, -0.4;
    const Eigen::Isometry3d T_vr_nom = withoutPitchAndRoll(T_vr_hmd);
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitY()).toRotationMatrix();
    ASSERT_LT((T_vr_nom.linear() - expected).norm(), 1e-9) << "psi " << psi << " theta " << theta;
    ASSERT_LT((T_vr_nom.translation() - T_vr_hmd.translation()).norm(), 1e-15);
  }
}

TEST(HeadAngles, WithoutPitchAndRollLookingStraightDownIsARotation) {
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
  T_vr_hmd.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T_vr_hmd.translation() << 0.1, 1.5, 0.2;
  const Eigen::Isometry3d T = withoutPitchAndRoll(T_vr_hmd);
  EXPECT_TRUE(T.matrix().allFinite());
  EXPECT_LT((T.linear() * T.linear().transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // The top of the head points along −z (forward of the unrotated space): yaw 0.
  EXPECT_LT((T.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  EXPECT_EQ(T.translation(), T_vr_hmd.translation());
}

}  // namespace
}  // namespace telesphere::link
