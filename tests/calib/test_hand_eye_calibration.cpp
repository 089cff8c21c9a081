// SPDX-License-Identifier: MIT
/// @brief Hand-eye calibration on simulated sessions (STYLE.md §20): the closed form is exact
///        without noise, Ceres recovers the three transforms from noisy corners, and samples that
///        cannot separate the unknowns are refused.
#include <gtest/gtest.h>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "calib/hand_eye_calibration.h"
#include "calib/hand_eye_samples.h"
#include "calib/synthetic/calibration_sessions.h"

namespace telesphere::calib {
namespace {

using calib::synthetic::lens1280;

SystemCalibration stereoCameras() {
  SystemCalibration system;
  system.cameras.push_back({"cam_l", lens1280(false).camera, 1280, 1024});
  system.cameras.push_back({"cam_r", lens1280(true).camera, 1280, 1024});
  system.T_cam_l_cam_r = calib::synthetic::trueTCamLCamR();
  return system;
}

void expectRecovered(const HandEyeResult& r, const calib::synthetic::HandEyeTruth& truth, double mm, double deg) {
  EXPECT_LT(calib::synthetic::translationError(r.T_flange_cam_l, truth.T_flange_cam_l), mm * 1e-3);
  EXPECT_LT(calib::synthetic::rotationErrorDeg(r.T_flange_cam_l, truth.T_flange_cam_l), deg);
  EXPECT_LT(calib::synthetic::translationError(r.T_robot_mount, truth.T_robot_mount), mm * 1e-3);
  EXPECT_LT(calib::synthetic::rotationErrorDeg(r.T_robot_mount, truth.T_robot_mount), deg);
  EXPECT_LT(calib::synthetic::translationError(r.T_wrist_marker, truth.T_wrist_marker), mm * 1e-3);
  EXPECT_LT(calib::synthetic::rotationErrorDeg(r.T_wrist_marker, truth.T_wrist_marker), deg);
}

TEST(HandEyeCalibration, ClosedFormIsExactWithoutNoise) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    calib::synthetic::trueTCamLCamR(), 0.1, 20, 0.0, 1);
  ASSERT_EQ(samples.size(), 20u);
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_TRUE(result) << result.failure().message;
  const calib::synthetic::HandEyeTruth init{result->initial[0], result->initial[1], result->initial[2]};
  EXPECT_LT(calib::synthetic::translationError(init.T_flange_cam_l, truth.T_flange_cam_l), 1e-6);
  EXPECT_LT(calib::synthetic::rotationErrorDeg(init.T_robot_mount, truth.T_robot_mount), 1e-5);
  EXPECT_LT(calib::synthetic::translationError(init.T_wrist_marker, truth.T_wrist_marker), 1e-6);
  expectRecovered(*result, truth, 1e-5, 1e-6);
}

TEST(HandEyeCalibration, RecoversTransformsFromNoisyCorners) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    calib::synthetic::trueTCamLCamR(), 0.1, 50, 0.3, 2);
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
  EXPECT_LT(calib::synthetic::translationError(result->T_flange_cam_l, truth.T_flange_cam_l),
            calib::synthetic::translationError(result->initial[0], truth.T_flange_cam_l) + 1e-4);
}

// The standard deviations describe the error: over seeded sessions the error of each transform
// stays within 4σ (per component, a Gaussian exceeds 4σ with 6e-5 probability), and σ shrinks
// with the sample count: from 12 to 48 samples by at least 1/√4 (more, because a dozen samples
// also spread the rotations less; 3.8× in this session).
TEST(HandEyeCalibration, StandardDeviationsDescribeTheError) {
  const auto truth = calib::synthetic::handEyeTruth();
  const std::array<Eigen::Isometry3d, 3> T_true{truth.T_flange_cam_l, truth.T_robot_mount, truth.T_wrist_marker};
  std::array<double, 2> sigma_t_mm{};
  for (int run = 0; run < 2; ++run) {
    const int n = run == 0 ? 12 : 48;
    const auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                      calib::synthetic::trueTCamLCamR(), 0.1, n, 0.3, 11 + run);
    HandEyeOptions options;
    options.min_samples = 5;
    const auto r = calibrateHandEye(stereoCameras(), 0.1, samples, options);
    ASSERT_TRUE(r) << r.failure().message;
    const std::array<Eigen::Isometry3d, 3> T_est{r->T_flange_cam_l, r->T_robot_mount, r->T_wrist_marker};
    for (std::size_t k = 0; k < 3; ++k) {
      const PoseStddev& sd = r->stddev[k];
      ASSERT_TRUE(sd.valid) << k;
      EXPECT_GT(sd.translation_m.minCoeff(), 1e-6) << k;
      EXPECT_GT(sd.rotation_deg.minCoeff(), 1e-5) << k;
      const Eigen::Vector3d dt = T_est[k].translation() - T_true[k].translation();
      // The rotation error in the parent frame, as the tangent is defined (exp([δ]×)·R).
      const Eigen::AngleAxisd da(T_true[k].linear() * T_est[k].linear().transpose());
      const Eigen::Vector3d dr = da.axis() * da.angle() * 180.0 / M_PI;
      for (int i = 0; i < 3; ++i) {
        EXPECT_LT(std::abs(dt[i]), 4.0 * sd.translation_m[i] + 1e-6) << "transform " << k << " axis " << i;
        EXPECT_LT(std::abs(dr[i]), 4.0 * sd.rotation_deg[i] + 1e-5) << "transform " << k << " axis " << i;
      }
    }
    sigma_t_mm[static_cast<std::size_t>(run)] = r->stddev[0].translation_m.norm() * 1e3;
    ASSERT_EQ(r->sample_fits.size(), samples.size());
    for (const HandEyeSampleFit& fit : r->sample_fits) {
      EXPECT_EQ(fit.corners, 8);
      EXPECT_LT(fit.rms_px, 1.5);
    }
  }
  EXPECT_GT(sigma_t_mm[0] / sigma_t_mm[1], 1.7) << sigma_t_mm[0] << " vs " << sigma_t_mm[1] << " mm";
  EXPECT_LT(sigma_t_mm[0] / sigma_t_mm[1], 8.0) << sigma_t_mm[0] << " vs " << sigma_t_mm[1] << " mm";
}

// A sample whose corners are 15 px off stands out in its fit; the others do not.
TEST(HandEyeCalibration, SampleFitsShowAnOutlier) {
  const auto truth = calib::synthetic::handEyeTruth();
  auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true), calib::synthetic::trueTCamLCamR(),
                                              0.1, 30, 0.3, 13);
  for (auto& px : *samples[7].corners_l) px += Eigen::Vector2d(15.0, -9.0);
  const auto r = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_TRUE(r) << r.failure().message;
  ASSERT_EQ(r->sample_fits.size(), 30u);
  for (const HandEyeSampleFit& fit : r->sample_fits) {
    if (fit.index == 7) {
      EXPECT_GT(fit.rms_px, 8.0);
    } else {
      EXPECT_LT(fit.rms_px, 2.0) << fit.index;
    }
  }
}

// Below 10 samples the closed form is not unique: without a starting T_flange_cam_l the solve
// says so; with one 1 cm and 2° off (the robot's current calibration) it initialises Z and Y
// from the marker poses and Ceres recovers all three from 6 samples.
TEST(HandEyeCalibration, FewSamplesNeedAStartingFlangeCamera) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    calib::synthetic::trueTCamLCamR(), 0.1, 6, 0.2, 14);
  HandEyeOptions options;
  options.min_samples = 5;
  auto r = calibrateHandEye(stereoCameras(), 0.1, samples, options);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.failure().code, CalibrationError::kTooFewViews);
  EXPECT_NE(r.failure().message.find("needs 10 samples (have 6) or a starting T_flange_cam_l"), std::string::npos)
      << r.failure().message;
  options.T_flange_cam_l_guess =
      truth.T_flange_cam_l * calib::synthetic::poseOf(Eigen::Vector3d(0.02, -0.025, 0.01), Eigen::Vector3d(0.006, -0.005, 0.006));
  r = calibrateHandEye(stereoCameras(), 0.1, samples, options);
  ASSERT_TRUE(r) << r.failure().message;
  // Six samples pin the transforms to a few millimetres (5.4 mm for the mount here), in the
  // right basin: the camera much nearer the truth than the start.
  expectRecovered(*r, truth, 10.0, 1.0);
  EXPECT_LT(calib::synthetic::translationError(r->T_flange_cam_l, truth.T_flange_cam_l),
            0.3 * calib::synthetic::translationError(*options.T_flange_cam_l_guess, truth.T_flange_cam_l));
}

// A still whose image and joints disagree (the marker 200 px away from where the joints put it)
// must not make every solve "diverged": the solve fits the rest and the sample stands out, so it
// can be marked and removed.
TEST(HandEyeCalibration, AGrossOutlierDoesNotFailTheSolve) {
  const auto truth = calib::synthetic::handEyeTruth();
  auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true), calib::synthetic::trueTCamLCamR(),
                                              0.1, 30, 0.3, 15);
  for (auto* corners : {&samples[4].corners_l, &samples[4].corners_r})
    for (auto& px : **corners) px += Eigen::Vector2d(200.0, -120.0);
  const auto r = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_TRUE(r) << r.failure().message;
  EXPECT_GT(std::max(r->rms_px_l, r->rms_px_r), 5.0);  // the overall RMS alone would have refused it
  for (const HandEyeSampleFit& fit : r->sample_fits) {
    if (fit.index == 4) {
      EXPECT_GT(fit.rms_px, 100.0);
    } else {
      EXPECT_LT(fit.rms_px, 3.0) << fit.index;
    }
  }
  expectRecovered(*r, truth, 5.0, 0.5);
}

// A real wizard run (tests/calib/data/hand_eye_closed_form_trap.yaml): the closed-form start
// alone ends in a wrong minimum; with the robot's T_flange_cam_l as a second start the solve
// keeps the better fit and recovers the truth.
TEST(HandEyeCalibration, AClosedFormTrapIsLeftThroughTheSecondStart) {
  const std::string src = TELESPHERE_SOURCE_DIR "/";
  const auto believed = loadCalibrationFile(src + "calib/data/sim_calibration.yaml");
  const auto truth = loadCalibrationFile(src + "tests/console/data/handeye_truth.yaml");
  const auto file = loadHandEyeSamples(src + "tests/calib/data/hand_eye_closed_form_trap.yaml");
  ASSERT_TRUE(believed && truth && file);
  ASSERT_EQ(file->samples.size(), 10u);
  SystemCalibration cameras = *believed;
  std::string error;
  for (CameraCalibration& c : cameras.cameras) {
    auto scaled = atResolution(c, 1280, 720, &error);
    ASSERT_TRUE(scaled) << error;
    c = *scaled;
  }
  const auto closed_form_only = calibrateHandEye(cameras, file->marker_size, file->samples);
  ASSERT_FALSE(closed_form_only);
  EXPECT_EQ(closed_form_only.failure().code, CalibrationError::kDiverged);

  HandEyeOptions options;
  options.T_flange_cam_l_guess = believed->T_flange_cam_l;
  const auto result = calibrateHandEye(cameras, file->marker_size, file->samples, options);
  ASSERT_TRUE(result) << result.failure().message;
  EXPECT_LT(std::max(result->rms_px_l, result->rms_px_r), 0.5);
  EXPECT_LT(calib::synthetic::translationError(result->T_flange_cam_l, *truth->T_flange_cam_l), 3e-3);
  EXPECT_LT(calib::synthetic::rotationErrorDeg(result->T_flange_cam_l, *truth->T_flange_cam_l), 0.3);
  EXPECT_LT(calib::synthetic::translationError(result->T_robot_mount, *truth->T_robot_mount), 10e-3);
  // The believed T_flange_cam_l was 11 mm off: the solve moved away from its start.
  EXPECT_GT(calib::synthetic::translationError(*believed->T_flange_cam_l, *truth->T_flange_cam_l), 5e-3);
  for (const PoseStddev& sd : result->stddev) EXPECT_TRUE(sd.valid);
}

TEST(HandEyeCalibration, RefusesHeadRotatingAboutOneAxis) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    calib::synthetic::trueTCamLCamR(), 0.1, 30, 0.3, 3,
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
  const auto truth = calib::synthetic::handEyeTruth();
  auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                              calib::synthetic::trueTCamLCamR(), 0.1, 30, 0.3, 4);
  // Wrist turning about its z axis only (the corners no longer matter to the check).
  for (std::size_t i = 0; i < samples.size(); ++i)
    samples[i].T_mount_wrist = calib::synthetic::poseOf(Eigen::Vector3d(0, 0, 0.1 * double(i)), Eigen::Vector3d(0.4, 0, 0.3));
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kNotIdentifiable);
  EXPECT_NE(result.failure().message.find("wrist"), std::string::npos);
}

TEST(HandEyeCalibration, RefusesTooFewSamples) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, lens1280(false), lens1280(true),
                                                    calib::synthetic::trueTCamLCamR(), 0.1, 5, 0.3, 5);
  const auto result = calibrateHandEye(stereoCameras(), 0.1, samples);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kTooFewViews);
}

}  // namespace
}  // namespace telesphere::calib
