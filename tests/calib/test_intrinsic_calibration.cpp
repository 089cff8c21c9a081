// SPDX-License-Identifier: MIT
/// @brief Intrinsic and stereo calibration on synthetic corners of the >180° double-sphere lens
///        (STYLE.md §20): ground truth → perturbed start or automatic initialisation → solve →
///        parameters recovered and cost fallen; views beyond 90° off-axis used; failures reported.
#include <gtest/gtest.h>

#include <algorithm>

#include "calib/intrinsic_calibration.h"
#include "calib/synthetic/calibration_sessions.h"

namespace telesphere::calib {
namespace {

using calib::synthetic::lens1280;
using calib::synthetic::testGrid;

constexpr double kNoisePx = 0.3;

CameraViews syntheticViews(const calib::synthetic::SyntheticCamera& cam, const std::vector<Eigen::Isometry3d>& T_cam_board,
                           std::uint32_t seed, const std::string& label = "cam_l") {
  std::mt19937 rng(seed);
  CameraViews views;
  views.label = label;
  views.width = cam.width;
  views.height = cam.height;
  for (const auto& T : T_cam_board) views.views.push_back(calib::synthetic::observeBoard(cam, testGrid(), T, kNoisePx, rng));
  return views;
}

TEST(IntrinsicCalibration, RecoversDoubleSphereFromPerturbedStart) {
  const auto cam = lens1280();
  std::mt19937 rng(3);
  const auto poses = calib::synthetic::spreadBoardPoses(cam, testGrid(), 20, 100.0 * M_PI / 180, rng);
  ASSERT_EQ(poses.size(), 20u);
  CameraViews views = syntheticViews(cam, poses, 11);
  // At least one corner beyond 90° off-axis is part of the data.
  int beyond = 0;
  for (std::size_t v = 0; v < poses.size(); ++v)
    for (int id : views.views[v].corner_ids) beyond += (poses[v] * testGrid().cornerPosition(id)).z() < 0;
  ASSERT_GT(beyond, 0);
  const Eigen::VectorXd truth = cam.camera.params();
  Eigen::VectorXd start = truth;
  start << truth[0] * 1.05, truth[1] * 0.96, truth[2] + 8, truth[3] - 6, truth[4] + 0.15, truth[5] - 0.08;
  views.initial_params = start;
  IntrinsicOptions options;
  const auto result = calibrateIntrinsics(testGrid(), {views}, options);
  ASSERT_TRUE(result) << result.failure().message;
  const Eigen::VectorXd p = result->cameras[0].calibration.camera.params();
  EXPECT_NEAR(p[0] / truth[0], 1.0, 2e-3);
  EXPECT_NEAR(p[1] / truth[1], 1.0, 2e-3);
  EXPECT_NEAR(p[2], truth[2], 0.5);
  EXPECT_NEAR(p[3], truth[3], 0.5);
  EXPECT_NEAR(p[4], truth[4], 0.01);
  EXPECT_NEAR(p[5], truth[5], 0.01);
  EXPECT_LT(result->final_cost, 0.1 * result->initial_cost);
  // Reprojection RMS of the 2-D error ≈ σ·√2 for isotropic noise σ per axis.
  EXPECT_NEAR(result->cameras[0].rms_px, kNoisePx * std::sqrt(2.0), 0.05);
  EXPECT_EQ(result->cameras[0].views_used, 20);
  ASSERT_EQ(result->cameras[0].param_stddev.size(), 6u);
  // The covariance's standard deviations are consistent with the actual error (within 5σ).
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(result->cameras[0].param_stddev[static_cast<std::size_t>(i)], 0.0);
    EXPECT_LT(std::abs(p[i] - truth[i]), 5 * result->cameras[0].param_stddev[static_cast<std::size_t>(i)] + 1e-9)
        << "parameter " << i;
  }
}

TEST(IntrinsicCalibration, GoodViewsMeetTheAccuracyGoalsAndAreSeparable) {
  // Views over the whole image, the rim included, strongly tilted; σ = 0.3 px; automatic start.
  const auto cam = lens1280();
  std::mt19937 rng(17);
  const auto poses = calib::synthetic::spreadBoardPoses(cam, testGrid(), 40, 100.0 * M_PI / 180, rng);
  ASSERT_EQ(poses.size(), 40u);
  const auto result = calibrateIntrinsics(testGrid(), {syntheticViews(cam, poses, 19)});
  ASSERT_TRUE(result) << result.failure().message;
  const auto& c = result->cameras[0];
  const Eigen::VectorXd p = c.calibration.camera.params(), truth = cam.camera.params();
  EXPECT_LT(std::abs(p[0] / truth[0] - 1), 1e-3) << p.transpose();  // focal error < 0.1 %
  EXPECT_LT(std::abs(p[1] / truth[1] - 1), 1e-3) << p.transpose();
  EXPECT_NEAR(c.rms_px / (kNoisePx * std::sqrt(2.0)), 1.0, 0.05);     // RMS within 5 % of the noise
  EXPECT_TRUE(c.degeneracy_warning.empty()) << c.degeneracy_warning;
  EXPECT_FALSE(result->degenerate());
  EXPECT_LT(c.focal_distortion_correlation, IntrinsicOptions{}.max_focal_correlation);
  ASSERT_EQ(c.param_correlation.rows(), 6);
  EXPECT_NEAR(c.param_correlation(4, 4), 1.0, 1e-9);
  EXPECT_NEAR(c.param_correlation(0, 4), c.param_correlation(4, 0), 1e-9);
}

TEST(IntrinsicCalibration, WarnsWhenFocalLengthAndDistortionAreNotSeparable) {
  // Every view fronto-parallel at the image centre: a longer focal length with more distortion
  // explains the corners as well. The solve must say so instead of answering confidently.
  const auto cam = lens1280();
  std::mt19937 rng(23);
  const auto poses = calib::synthetic::frontoParallelCentreBoardPoses(testGrid(), 12, rng);
  std::vector<std::string> progress;
  IntrinsicOptions options;
  options.progress = [&](const std::string& line) { progress.push_back(line); };
  const auto result = calibrateIntrinsics(testGrid(), {syntheticViews(cam, poses, 29)}, options);
  ASSERT_TRUE(result) << result.failure().message;
  const auto& c = result->cameras[0];
  EXPECT_TRUE(result->degenerate());
  EXPECT_GT(c.focal_distortion_correlation, options.max_focal_correlation);
  EXPECT_NE(c.degeneracy_warning.find("cam_l: the views do not separate the focal length from xi, alpha"),
            std::string::npos)
      << c.degeneracy_warning;
  EXPECT_NE(c.degeneracy_warning.find("image rim"), std::string::npos) << c.degeneracy_warning;
  EXPECT_TRUE(std::any_of(progress.begin(), progress.end(),
                          [](const std::string& l) { return l.rfind("WARNING: cam_l:", 0) == 0; }));
  // Without the covariance there is no separability verdict (and no false alarm).
  options.covariance = false;
  const auto unchecked = calibrateIntrinsics(testGrid(), {syntheticViews(cam, poses, 29)}, options);
  ASSERT_TRUE(unchecked);
  EXPECT_TRUE(unchecked->cameras[0].degeneracy_warning.empty());
  EXPECT_TRUE(std::isnan(unchecked->cameras[0].focal_distortion_correlation));
}

TEST(IntrinsicCalibration, CalibratesTheStereoPairFromAutomaticInitialisation) {
  const auto cam_l = lens1280(false), cam_r = lens1280(true);
  const Eigen::Isometry3d T_l_r = calib::synthetic::trueTCamLCamR();
  std::mt19937 rng(5);
  const auto poses = calib::synthetic::spreadBoardPoses(cam_l, testGrid(), 16, 90.0 * M_PI / 180, rng);
  std::vector<Eigen::Isometry3d> poses_r;
  for (const auto& T : poses) poses_r.push_back(T_l_r.inverse() * T);
  std::vector<CameraViews> views = {syntheticViews(cam_l, poses, 21, "cam_l"),
                                    syntheticViews(cam_r, poses_r, 22, "cam_r")};
  IntrinsicOptions options;
  options.covariance = false;
  int progress_lines = 0;
  options.progress = [&](const std::string&) { ++progress_lines; };
  const auto result = calibrateIntrinsics(testGrid(), views, options);
  ASSERT_TRUE(result) << result.failure().message;
  EXPECT_GT(progress_lines, 3);
  for (int c = 0; c < 2; ++c) {
    const Eigen::VectorXd truth = (c == 0 ? cam_l : cam_r).camera.params();
    const Eigen::VectorXd p = result->cameras[static_cast<std::size_t>(c)].calibration.camera.params();
    EXPECT_NEAR(p[0] / truth[0], 1.0, 2e-3) << "camera " << c;
    EXPECT_NEAR(p[2], truth[2], 0.5) << "camera " << c;
    EXPECT_NEAR(p[4], truth[4], 0.015) << "camera " << c;
    EXPECT_NEAR(p[5], truth[5], 0.015) << "camera " << c;
    EXPECT_NEAR(result->cameras[static_cast<std::size_t>(c)].rms_px, kNoisePx * std::sqrt(2.0), 0.06);
  }
  ASSERT_TRUE(result->T_cam_l_cam_r);
  EXPECT_LT(calib::synthetic::translationError(*result->T_cam_l_cam_r, T_l_r), 1e-3);
  EXPECT_LT(calib::synthetic::rotationErrorDeg(*result->T_cam_l_cam_r, T_l_r), 0.05);
  EXPECT_LT(result->final_cost, result->initial_cost);
  const SystemCalibration system = result->toSystemCalibration();
  EXPECT_FALSE(system.inconsistency()) << system.inconsistency()->second;
}

TEST(IntrinsicCalibration, StereoExtrinsicStddevMatchesTheScatterOverNoiseSeeds) {
  // The same 16 board poses observed with 12 seeds of 0.3 px noise: the reported σ of
  // T_cam_l_cam_r must describe how far the solves actually scatter around the truth (the
  // normalised errors' RMS near 1: far above when σ is too small, far below when too large).
  const auto cam_l = lens1280(false), cam_r = lens1280(true);
  const Eigen::Isometry3d T_l_r = calib::synthetic::trueTCamLCamR();
  std::mt19937 rng(7);
  const auto poses = calib::synthetic::spreadBoardPoses(cam_l, testGrid(), 16, 90.0 * M_PI / 180, rng);
  std::vector<Eigen::Isometry3d> poses_r;
  for (const auto& T : poses) poses_r.push_back(T_l_r.inverse() * T);
  double sum_z2 = 0;
  int n = 0;
  for (std::uint32_t seed = 0; seed < 12; ++seed) {
    std::vector<CameraViews> views = {syntheticViews(cam_l, poses, 100 + seed, "cam_l"),
                                      syntheticViews(cam_r, poses_r, 200 + seed, "cam_r")};
    views[0].initial_params = cam_l.camera.params();
    views[1].initial_params = cam_r.camera.params();
    const auto result = calibrateIntrinsics(testGrid(), views, IntrinsicOptions{});
    ASSERT_TRUE(result) << result.failure().message;
    ASSERT_TRUE(result->T_cam_l_cam_r);
    const PoseStddev& sd = result->T_cam_l_cam_r_stddev;
    ASSERT_TRUE(sd.valid);
    const Eigen::Isometry3d& T = *result->T_cam_l_cam_r;
    const Eigen::AngleAxisd turn(T.linear() * T_l_r.linear().transpose());  // about cam_l's axes
    const Eigen::Vector3d dr_deg = turn.angle() * turn.axis() * 180 / M_PI;
    const Eigen::Vector3d dt_m = T.translation() - T_l_r.translation();
    for (int i = 0; i < 3; ++i) {
      ASSERT_GT(sd.translation_m[i], 0.0);
      ASSERT_GT(sd.rotation_deg[i], 0.0);
      sum_z2 += std::pow(dt_m[i] / sd.translation_m[i], 2) + std::pow(dr_deg[i] / sd.rotation_deg[i], 2);
      n += 2;
    }
    if (seed == 0)
      std::printf("σ t %.3f %.3f %.3f mm, r %.4f %.4f %.4f deg; error t %.3f %.3f %.3f mm\n", sd.translation_m.x() * 1e3,
                  sd.translation_m.y() * 1e3, sd.translation_m.z() * 1e3, sd.rotation_deg.x(), sd.rotation_deg.y(),
                  sd.rotation_deg.z(), dt_m.x() * 1e3, dt_m.y() * 1e3, dt_m.z() * 1e3);
  }
  const double rms_z = std::sqrt(sum_z2 / n);
  std::printf("normalised error RMS over %d axis-solves: %.3f\n", n, rms_z);
  EXPECT_GT(rms_z, 0.6);
  EXPECT_LT(rms_z, 1.5);
}

TEST(IntrinsicCalibration, ReportsTargetNeverSeenAndTooFewViews) {
  const auto cam = lens1280();
  CameraViews none;
  none.width = cam.width;
  none.height = cam.height;
  none.views.resize(5);
  auto result = calibrateIntrinsics(testGrid(), {none});
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kTargetNeverSeen);

  std::mt19937 rng(7);
  const auto poses = calib::synthetic::spreadBoardPoses(cam, testGrid(), 2, 0.5, rng);
  result = calibrateIntrinsics(testGrid(), {syntheticViews(cam, poses, 1)});
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kTooFewViews);
  EXPECT_NE(result.failure().message.find("only 2 usable views"), std::string::npos);
}

TEST(IntrinsicCalibration, ReportsADivergingSolveForAWrongTarget) {
  const auto cam = lens1280();
  std::mt19937 rng(9);
  const auto poses = calib::synthetic::spreadBoardPoses(cam, testGrid(), 6, 1.0, rng);
  CameraViews views = syntheticViews(cam, poses, 2);
  // Shuffled corner ids within each view: no camera explains these observations.
  for (auto& v : views.views) std::shuffle(v.corner_ids.begin(), v.corner_ids.end(), rng);
  IntrinsicOptions options;
  options.covariance = false;
  options.max_iterations = 30;
  const auto result = calibrateIntrinsics(testGrid(), {views}, options);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.failure().code, CalibrationError::kDiverged) << result.failure().message;
}

TEST(IntrinsicCalibration, FitsTheSimplerModelsOnTheSameData) {
  // Model selection: EUCM fits the double-sphere lens nearly as well; pinhole cannot (>180°).
  const auto cam = lens1280();
  std::mt19937 rng(13);
  const auto poses = calib::synthetic::spreadBoardPoses(cam, testGrid(), 12, 95.0 * M_PI / 180, rng);
  CameraViews views = syntheticViews(cam, poses, 4);
  IntrinsicOptions options;
  options.covariance = false;
  views.model = "eucm";
  const auto eucm = calibrateIntrinsics(testGrid(), {views}, options);
  ASSERT_TRUE(eucm) << eucm.failure().message;
  EXPECT_LT(eucm->cameras[0].rms_px, 0.6);
  views.model = "kb4";
  const auto kb4 = calibrateIntrinsics(testGrid(), {views}, options);
  ASSERT_TRUE(kb4) << kb4.failure().message;
  EXPECT_LT(kb4->cameras[0].rms_px, 0.6);
}

}  // namespace
}  // namespace telesphere::calib
