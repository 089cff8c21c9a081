// SPDX-License-Identifier: MIT
/// @brief Hand-eye calibration on simulated sessions (STYLE.md §20): the closed form is exact
///        without noise, Ceres recovers the three transforms from noisy corners, and samples that
///        cannot separate the unknowns are refused.
#include <gtest/gtest.h>

#include "calib/hand_eye_calibration.h"
#include "tests/calib/calib_synthetic.h"

namespace telesphere::calib {
namespace {

using test::lens1280;

SystemCalibration stereoCameras() {
  SystemCalibration system;
  system.cameras.push_back({"cam_l", lens1280(false).camera, 1280, 1024});
  system.cameras.push_back({"cam_r", lens1280(true).camera, 1280, 1024});
  system.T_cam_l_cam_r = test::trueTCamLCamR();
  return system;
}

void expectRecovered(const HandEyeResult& r, const test::HandEyeTruth& truth, double mm, double deg) {
  EXPECT_LT(test::translationError(r.T_flange_cam_l, truth.T_flange_cam_l), mm * 1e-3);
  EXPECT_LT(test::rotationErrorDeg(r.T_flange_cam_l, truth.T_flange_cam_l), deg);
  EXPECT_LT(test::translationError(r.T_robot_mount, truth.T_robot_mount), mm * 1e-3);
  EXPECT_LT(test::rotationErrorDeg(r.T_robot_mount, truth.T_robot_mount), deg);
  EXPECT_LT(test::translationError(r.T_wrist_marker, truth.T_wrist_marker), mm * 1e-3);
  EXPECT_LT(test::rotationErrorDeg(r.T_wrist_marker, truth.T_wrist_marker), deg);
}

TEST(HandEyeCalibration, ClosedFormIsExactWithoutNoise) {
  const auto truth = test::handEyeTruth();
  const auto samples = test::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    test::trueTCamLCamR(), 0.1, 20, 0.0, 1);
  ASSERT_EQ(samples.size(), 20u);
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_TRUE(result) << result.failure().message;
  const test::HandEyeTruth init{result->initial[0], result->initial[1], result->initial[2]};
  EXPECT_LT(test::translationError(init.T_flange_cam_l, truth.T_flange_cam_l), 1e-6);
  EXPECT_LT(test::rotationErrorDeg(init.T_robot_mount, truth.T_robot_mount), 1e-5);
  EXPECT_LT(test::translationError(init.T_wrist_marker, truth.T_wrist_marker), 1e-6);
  expectRecovered(*result, truth, 1e-5, 1e-6);
}

TEST(HandEyeCalibration, RecoversTransformsFromNoisyCorners) {
  const auto truth = test::handEyeTruth();
  const auto samples = test::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    test::trueTCamLCamR(), 0.1, 50, 0.3, 2);
  ASSERT_EQ(samples.size(), 50u);
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_TRUE(result) << result.failure().message;
  EXPECT_TRUE(result->identifiability.ok);
  EXPECT_LT(result->final_cost, result->initial_cost);
  EXPECT_NEAR(result->rms_px_l, 0.3 * std::sqrt(2.0), 0.08);
  EXPECT_NEAR(result->rms_px_r, 0.3 * std::sqrt(2.0), 0.08);
  // 1280×1024 at ~315 px focal length, a 10 cm marker: a few millimetres at most.
  expectRecovered(*result, truth, 3.0, 0.3);
  // The closed form alone is worse than the refined solution.
  EXPECT_LT(test::translationError(result->T_flange_cam_l, truth.T_flange_cam_l),
            test::translationError(result->initial[0], truth.T_flange_cam_l) + 1e-4);
}

TEST(HandEyeCalibration, RefusesHeadRotatingAboutOneAxis) {
  const auto truth = test::handEyeTruth();
  const auto samples = test::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    test::trueTCamLCamR(), 0.1, 30, 0.3, 3,
                                                    /*head_two_axes=*/false);
  const auto check = checkHandEyeIdentifiability(samples);
  EXPECT_FALSE(check.ok);
  EXPECT_LT(check.head_axis_spread_deg, 1.0);
  EXPECT_GT(check.wrist_axis_spread_deg, 10.0);
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kNotIdentifiable);
  EXPECT_NE(result.failure().message.find("head arm"), std::string::npos);
}

TEST(HandEyeCalibration, RefusesWristRotatingAboutOneAxis) {
  const auto truth = test::handEyeTruth();
  auto samples = test::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                              test::trueTCamLCamR(), 0.1, 30, 0.3, 4);
  // Wrist turning about its z axis only (the corners no longer matter to the check).
  for (std::size_t i = 0; i < samples.size(); ++i)
    samples[i].T_mount_wrist = test::poseOf(Eigen::Vector3d(0, 0, 0.1 * double(i)), Eigen::Vector3d(0.4, 0, 0.3));
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kNotIdentifiable);
  EXPECT_NE(result.failure().message.find("wrist"), std::string::npos);
}

TEST(HandEyeCalibration, RefusesTooFewSamples) {
  const auto truth = test::handEyeTruth();
  const auto samples = test::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    test::trueTCamLCamR(), 0.1, 5, 0.3, 5);
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kTooFewViews);
}

}  // namespace
}  // namespace telesphere::calib
