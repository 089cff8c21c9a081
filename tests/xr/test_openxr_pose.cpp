// SPDX-License-Identifier: MIT
/// @brief The OpenXR boundary: XrPosef → T_base_space, view validity flags, and the test
///        scene's nominal pose (pitch and roll removed, yaw kept) and eye midpoint.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "xr/openxr/openxr_pose.h"
#include "xr/openxr/openxr_test_scene.h"

namespace telesphere::xr {
namespace {

XrPosef openXrPoseTestPose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  XrPosef p{};
  p.orientation = {float(q.x()), float(q.y()), float(q.z()), float(q.w())};
  p.position = {float(t.x()), float(t.y()), float(t.z())};
  return p;
}

TEST(OpenXrPose, PoseMapsPointsFromTheLocatedSpaceIntoTheBase) {
  // An eye 1.6 m up, turned 90° left (about +y): its forward (−z) points along −x in vr.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  const Eigen::Isometry3d T_vr_eye = openxr::isometryFromXrPose(openXrPoseTestPose(q, {0.1, 1.6, -0.2}));
  const Eigen::Vector3d p_vr = T_vr_eye * Eigen::Vector3d(0, 0, -1);
  EXPECT_NEAR(p_vr.x(), 0.1 - 1.0, 1e-6);
  EXPECT_NEAR(p_vr.y(), 1.6, 1e-6);
  EXPECT_NEAR(p_vr.z(), -0.2, 1e-6);
  EXPECT_FALSE(render::checkPose(T_vr_eye).has_value());
}

TEST(OpenXrPose, SlightlyDenormalisedQuaternionsAreNormalisedAndZeroOnesRefused) {
  XrPosef p{};
  p.orientation = {0.0f, 0.0f, 0.0f, 1.02f};
  EXPECT_FALSE(render::checkPose(openxr::isometryFromXrPose(p)).has_value());
  p.orientation = {0.0f, 0.0f, 0.0f, 0.0f};
  EXPECT_TRUE(render::checkPose(openxr::isometryFromXrPose(p)).has_value()) << "never rendered";
}

TEST(OpenXrPose, ViewsNeedBothOrientationAndPositionValid) {
  EXPECT_TRUE(openxr::viewPoseValid(XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                            XR_VIEW_STATE_ORIENTATION_TRACKED_BIT));
  EXPECT_FALSE(openxr::viewPoseValid(XR_VIEW_STATE_ORIENTATION_VALID_BIT));
  EXPECT_FALSE(openxr::viewPoseValid(XR_VIEW_STATE_POSITION_VALID_BIT));
  EXPECT_FALSE(openxr::viewPoseValid(0));
}

TEST(OpenXrPose, MidpointOfTwoEyesIsTheHmd) {
  Eigen::Isometry3d l = Eigen::Isometry3d::Identity(), r = Eigen::Isometry3d::Identity();
  l.translation() << -0.032, 1.6, 0;
  r.translation() << 0.032, 1.6, 0;
  r.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Isometry3d m = openxr::midpointPose(l, r);
  EXPECT_LT((m.translation() - Eigen::Vector3d(0, 1.6, 0)).norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(m.linear()).angle(), 0.1, 1e-12);
}

TEST(OpenXrTestScene, CameraAndImageAreConsistentAndSeeTheCentreCross) {
  const auto camera = openxr::OpenXrTestScene::camera();
  const render::SourceImage image = openxr::OpenXrTestScene::image();
  ASSERT_TRUE(image.consistent());
  EXPECT_EQ(image.width, openxr::OpenXrTestScene::kImageWidth);
  Eigen::Vector2d px;
  ASSERT_TRUE(camera.project(Eigen::Vector3d(0, 0, 1), px));
  const Eigen::Vector4d centre = image.sample(px);
  EXPECT_NEAR(centre.x(), 1.0, 1e-9);
  EXPECT_NEAR(centre.y(), 1.0, 1e-9);
  EXPECT_NEAR(centre.z(), 1.0, 1e-9);
  EXPECT_GT(camera.maxAngle(), M_PI / 2) << "a fisheye: the headset's view is covered";
}

}  // namespace
}  // namespace telesphere::xr
