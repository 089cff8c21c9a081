// SPDX-License-Identifier: MIT
/// @brief VirtualHead: start pose and axes, walking in the yaw frame after a turn, mouse look
///        direction and pitch clamp, yaw wrap, refused and clamped time steps, a rotation that
///        stays orthonormal over a long random walk, reset.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "xr/desktop/virtual_head.h"

namespace telesphere::xr {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d viewDirection(const desktop::VirtualHead& head) {
  return head.pose().linear() * Eigen::Vector3d(0, 0, -1);  // hmd −z in vr
}

TEST(VirtualHead, StartsStandingAndLookingAlongMinusZ) {
  const desktop::VirtualHead head;
  const Eigen::Isometry3d T_vr_hmd = head.pose();
  EXPECT_TRUE(T_vr_hmd.translation().isApprox(Eigen::Vector3d(0, 1.6, 0), 1e-15));
  EXPECT_TRUE(T_vr_hmd.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  const desktop::VirtualHead seated(desktop::VirtualHeadSettings{.start_height = 0.0});
  EXPECT_TRUE(seated.pose().translation().isZero(0.0));
}

TEST(VirtualHead, ForwardIsWhereItLooksAndOppositeKeysCancel) {
  desktop::VirtualHead head;
  desktop::VirtualHeadInput input;
  input.forward = true;
  ASSERT_TRUE(head.step(input, 0.1));  // 0.5 m/s · 0.1 s
  EXPECT_TRUE(head.position().isApprox(Eigen::Vector3d(0, 1.6, -0.05), 1e-12));
  input.back = true;
  ASSERT_TRUE(head.step(input, 0.1));
  EXPECT_TRUE(head.position().isApprox(Eigen::Vector3d(0, 1.6, -0.05), 1e-12));
  input = {};
  input.up = true;
  input.right = true;  // diagonal: still 0.5 m/s in total
  ASSERT_TRUE(head.step(input, 0.1));
  const double d = 0.05 / std::sqrt(2.0);
  EXPECT_TRUE(head.position().isApprox(Eigen::Vector3d(d, 1.6 + d, -0.05), 1e-12));
}

TEST(VirtualHead, TurningLeft90DegreesThenForwardMovesAlongMinusX) {
  desktop::VirtualHead head;
  desktop::VirtualHeadInput turn;
  turn.turn_left = true;  // 1 rad/s
  const int steps = 100;
  for (int i = 0; i < steps; ++i) ASSERT_TRUE(head.step(turn, kPi / 2.0 / steps));
  EXPECT_NEAR(head.yaw(), kPi / 2.0, 1e-12);
  EXPECT_TRUE(viewDirection(head).isApprox(Eigen::Vector3d(-1, 0, 0), 1e-12));

  // Looking down as well must not make "forward" dig into the floor.
  desktop::VirtualHeadInput look_down;
  look_down.look = true;
  look_down.mouse_dy_px = 100.0;  // 0.3 rad down
  ASSERT_TRUE(head.step(look_down, 0.0));
  EXPECT_NEAR(head.pitch(), -0.3, 1e-12);

  desktop::VirtualHeadInput walk;
  walk.forward = true;
  ASSERT_TRUE(head.step(walk, 0.1));
  EXPECT_TRUE(head.position().isApprox(Eigen::Vector3d(-0.05, 1.6, 0), 1e-12));
  walk = {};
  walk.right = true;  // now right is −z
  ASSERT_TRUE(head.step(walk, 0.1));
  EXPECT_TRUE(head.position().isApprox(Eigen::Vector3d(-0.05, 1.6, -0.05), 1e-12));
}

TEST(VirtualHead, MouseRightTurnsRightAndOnlyWhileLooking) {
  desktop::VirtualHead head;
  desktop::VirtualHeadInput input;
  input.mouse_dx_px = 100.0;
  ASSERT_TRUE(head.step(input, 0.0));  // button not held: ignored
  EXPECT_EQ(head.yaw(), 0.0);
  input.look = true;
  ASSERT_TRUE(head.step(input, 0.0));
  EXPECT_NEAR(head.yaw(), -0.3, 1e-12);
  EXPECT_GT(viewDirection(head).x(), 0.2);  // looks to the right (+x)
  input.mouse_dx_px = 0.0;
  input.mouse_dy_px = -100.0;  // mouse up → looks up
  ASSERT_TRUE(head.step(input, 0.0));
  EXPECT_NEAR(head.pitch(), 0.3, 1e-12);
  EXPECT_GT(viewDirection(head).y(), 0.2);
}

TEST(VirtualHead, PitchIsClampedAtTheExtremes) {
  desktop::VirtualHead head;
  desktop::VirtualHeadInput input;
  input.look = true;
  input.mouse_dy_px = -1e9;  // a huge upward mouse flick
  ASSERT_TRUE(head.step(input, 0.0));
  EXPECT_EQ(head.pitch(), desktop::VirtualHead::kMaxPitch);
  EXPECT_NEAR(viewDirection(head).y(), std::sin(89.0 * kPi / 180.0), 1e-12);
  EXPECT_LT(viewDirection(head).z(), 0.0);  // not flipped over the pole
  input.mouse_dy_px = 1e9;
  ASSERT_TRUE(head.step(input, 0.0));
  EXPECT_EQ(head.pitch(), -desktop::VirtualHead::kMaxPitch);
  input = {};
  input.look_down = true;  // keys cannot push past the clamp either
  ASSERT_TRUE(head.step(input, 0.1));
  EXPECT_EQ(head.pitch(), -desktop::VirtualHead::kMaxPitch);
}

TEST(VirtualHead, YawWrapsIntoMinusPiToPi) {
  desktop::VirtualHead head;
  desktop::VirtualHeadInput input;
  input.look = true;
  input.mouse_dx_px = -(2.5 * kPi) / 0.003;  // 450° to the left
  ASSERT_TRUE(head.step(input, 0.0));
  EXPECT_NEAR(head.yaw(), kPi / 2.0, 1e-9);
  input.mouse_dx_px = (kPi / 2.0 + kPi) / 0.003;  // 270° to the right: exactly −π → +π
  ASSERT_TRUE(head.step(input, 0.0));
  EXPECT_LE(head.yaw(), kPi);
  EXPECT_GT(head.yaw(), -kPi);
  EXPECT_NEAR(std::abs(head.yaw()), kPi, 1e-9);
}

TEST(VirtualHead, BadTimeStepsAreRefusedAndHugeOnesClamped) {
  desktop::VirtualHead head;
  desktop::VirtualHeadInput input;
  input.forward = true;
  input.look = true;
  input.mouse_dx_px = 10.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double dt_s : {nan, inf, -inf, -0.01}) {
    EXPECT_FALSE(head.step(input, dt_s)) << dt_s;
    EXPECT_TRUE(head.pose().isApprox(desktop::VirtualHead().pose(), 0.0)) << "changed by dt " << dt_s;
  }
  desktop::VirtualHeadInput bad_mouse = input;
  bad_mouse.mouse_dy_px = nan;
  EXPECT_FALSE(head.step(bad_mouse, 0.01));
  bad_mouse.mouse_dy_px = 0.0;
  bad_mouse.mouse_dx_px = std::numeric_limits<double>::max();
  EXPECT_TRUE(head.step(bad_mouse, 0.0));  // max · 0.003 rad/px is finite: accepted, wrapped
  EXPECT_TRUE(std::isfinite(head.yaw()));
  desktop::VirtualHead sensitive(desktop::VirtualHeadSettings{.mouse_sensitivity_rad_px = 10.0});
  EXPECT_FALSE(sensitive.step(bad_mouse, 0.0));  // max · 10 rad/px overflows: refused
  EXPECT_EQ(sensitive.yaw(), 0.0);
  head.reset();

  input.look = false;
  ASSERT_TRUE(head.step(input, 3600.0));  // a stalled window: one kMaxStepS step at most
  EXPECT_NEAR(head.position().z(), -0.5 * desktop::VirtualHead::kMaxStepS, 1e-12);
}

TEST(VirtualHead, RotationStaysOrthonormalOverALongRandomWalk) {
  std::mt19937 rng(20240607);
  std::uniform_int_distribution<int> bit(0, 1);
  std::uniform_real_distribution<double> mouse(-300.0, 300.0);
  std::uniform_real_distribution<double> dt(0.0, 0.2);
  desktop::VirtualHead head;
  for (int i = 0; i < 100000; ++i) {
    desktop::VirtualHeadInput input;
    input.forward = bit(rng);
    input.back = bit(rng);
    input.left = bit(rng);
    input.right = bit(rng);
    input.up = bit(rng);
    input.down = bit(rng);
    input.turn_left = bit(rng);
    input.look_up = bit(rng);
    input.look = bit(rng);
    input.mouse_dx_px = mouse(rng);
    input.mouse_dy_px = mouse(rng);
    ASSERT_TRUE(head.step(input, dt(rng)));
  }
  const Eigen::Isometry3d T_vr_hmd = head.pose();
  const Eigen::Matrix3d R = T_vr_hmd.linear();
  EXPECT_TRUE((R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_NEAR((R * Eigen::Vector3d::UnitX()).y(), 0.0, 1e-12);  // never any roll
  EXPECT_LE(std::abs(head.pitch()), desktop::VirtualHead::kMaxPitch);
  EXPECT_TRUE(T_vr_hmd.translation().allFinite());
}

TEST(VirtualHead, ResetReturnsToTheStartPose) {
  desktop::VirtualHead head(desktop::VirtualHeadSettings{.speed_m_s = 2.0, .start_height = 1.2});
  desktop::VirtualHeadInput input;
  input.forward = input.left = input.down = input.look = true;
  input.mouse_dx_px = 123.0;
  input.mouse_dy_px = -45.0;
  ASSERT_TRUE(head.step(input, 0.05));
  ASSERT_FALSE(head.pose().isApprox(desktop::VirtualHead(head.settings()).pose(), 1e-6));
  head.reset();
  EXPECT_TRUE(head.position().isApprox(Eigen::Vector3d(0, 1.2, 0), 0.0));
  EXPECT_EQ(head.yaw(), 0.0);
  EXPECT_EQ(head.pitch(), 0.0);
  EXPECT_TRUE(head.pose().linear().isApprox(Eigen::Matrix3d::Identity(), 0.0));
}

}  // namespace
}  // namespace telesphere::xr
