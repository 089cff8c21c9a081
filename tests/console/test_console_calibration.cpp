// SPDX-License-Identifier: MIT
/// @brief The calibration wizards' Qt-free logic (issue #15): the view plan puts the board where
///        it was asked to (seeded random start poses, board positions, rolls; round trip through
///        the camera model), the board centre from one view, the collector's gates and coverage,
///        and the done rule's every check with its number.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "console/calibration/intrinsics_collector.h"
#include "console/calibration/intrinsics_done_rule.h"
#include "console/calibration/intrinsics_procedure.h"
#include "console/calibration/intrinsics_view_plan.h"
#include "console/calibration/hand_eye_collector.h"
#include "console/calibration/calibration_change.h"
#include "calib/target_render.h"
#include "robot/link/link_pose.h"
#include "calib/synthetic/calibration_sessions.h"

namespace telesphere::console::calibration {
namespace {

calib::CameraCalibration simCamera(int width = 1920, int height = 1080) {
  auto loaded = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  EXPECT_TRUE(loaded);
  std::string error;
  return *calib::atResolution(loaded->cameras[0], width, height, &error);
}

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

/// The corners of `grid` seen through `camera` from T_cam_board (those that project).
calib::TargetObservation observe(const calib::AprilGrid& grid, const calib::GenericCamera& camera,
                                 const Eigen::Isometry3d& T_cam_board) {
  calib::TargetObservation o;
  for (int id = 0; id < grid.numCorners(); ++id) {
    Eigen::Vector2d px;
    if (camera.project(T_cam_board * grid.cornerPosition(id), px)) {
      o.corner_ids.push_back(id);
      o.corners_px.push_back(px);
    }
  }
  return o;
}

TEST(IntrinsicsViewPlan, EachPoseShowsTheBoardCentreAtItsTargetPixelEvenBeyond90Degrees) {
  const calib::CameraCalibration cam = simCamera();
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ViewPlanOptions options;
  options.targets = ViewPlanOptions::innerTargets();
  for (const Eigen::Vector2d& t : ViewPlanOptions::outerTargets()) options.targets.push_back(t);
  int checked = 0, beyond_90 = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Isometry3d T_robot_head0 = Eigen::Isometry3d::Identity();
    T_robot_head0.linear() = randomRotation(rng);
    T_robot_head0.translation() = Eigen::Vector3d(0.4, 0, 0.45) + 0.1 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    Eigen::Isometry3d T_head_cam = Eigen::Isometry3d::Identity();
    T_head_cam.linear() = randomRotation(rng);
    T_head_cam.translation() = 0.08 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    // The board in view at the start (as the procedure requires), somewhere in the image's inner half.
    const Eigen::Isometry3d T_robot_cam0 = T_robot_head0 * T_head_cam;
    Eigen::Vector3d d_cam;
    ASSERT_TRUE(cam.camera.unproject(Eigen::Vector2d((0.5 + 0.25 * u(rng)) * cam.width, (0.5 + 0.25 * u(rng)) * cam.height), d_cam));
    const Eigen::Vector3d p_robot_board = T_robot_cam0 * ((0.6 + 0.4 * (u(rng) + 1)) * d_cam.normalized());
    const auto plan = planIntrinsicViews(T_robot_head0, T_head_cam, p_robot_board, cam.camera, cam.width, cam.height, options);
    // Every target is inside this model's domain; a rim target opposite the board may need a
    // turn beyond 150° and is left out (rare: counted below).
    EXPECT_GE(plan.size() + 1, options.targets.size());
    for (std::size_t i = 0; i < plan.size(); ++i) {
      EXPECT_LE(Eigen::AngleAxisd(T_robot_head0.linear().transpose() * plan[i].T_robot_head.linear()).angle() * 180 / M_PI,
                options.max_turn_deg);
      const Eigen::Isometry3d T_robot_cam = plan[i].T_robot_head * T_head_cam;
      EXPECT_TRUE(T_robot_cam.linear().isUnitary(1e-9));
      Eigen::Vector2d px;
      const Eigen::Vector3d p_cam = T_robot_cam.inverse() * p_robot_board;
      ASSERT_TRUE(cam.camera.project(p_cam, px)) << trial << " " << i;
      EXPECT_LT((px - plan[i].target_px).norm(), 1e-6)
          << trial << " " << i << " turn " << Eigen::AngleAxisd(T_robot_head0.linear().transpose() * plan[i].T_robot_head.linear()).angle() * 180 / M_PI
          << " dist " << (p_robot_board - T_robot_head0.translation()).norm() << " offset " << T_head_cam.translation().norm();
      // The head position is the start's plus the offset used in turn.
      const Eigen::Vector3d offset = plan[i].T_robot_head.translation() - T_robot_head0.translation();
      EXPECT_TRUE(std::any_of(options.offsets_m.begin(), options.offsets_m.end(),
                              [&](const Eigen::Vector3d& o) { return (offset - o).norm() < 1e-12; }));
      if (calib::polarAngleDeg(cam.camera, px) > 90.0) ++beyond_90;
      ++checked;
    }
  }
  EXPECT_GE(checked, 0.99 * 20 * double(options.targets.size()));
  // A turn beyond the bound is left out: the board behind the camera.
  {
    ViewPlanOptions behind;
    behind.targets = {{0.5, 0.5}};
    behind.offsets_m = {Eigen::Vector3d::Zero()};
    EXPECT_TRUE(planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.01, 0, -1),
                                   cam.camera, cam.width, cam.height, behind).empty());
    behind.max_turn_deg = 180.0;
    EXPECT_EQ(planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.01, 0, -1),
                                 cam.camera, cam.width, cam.height, behind).size(), 1u);
  }
  EXPECT_GT(beyond_90, 20 * 4);  // the rim targets lie beyond 90° off axis
  // A target outside the model's domain (the image's extreme corner) is left out.
  options.targets = {{0.0, 0.0}, {0.5, 0.5}};
  const auto plan = planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(),
                                       Eigen::Vector3d(0, 0, 1), cam.camera, cam.width, cam.height, options);
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_NEAR(plan[0].target_px.x(), 0.5 * (cam.width - 1), 1e-9);
}

TEST(IntrinsicsViewPlan, TheRollTurnsTheBoardAboutItsOwnDirection) {
  const calib::CameraCalibration cam = simCamera();
  ViewPlanOptions options;
  options.targets = {{0.5, 0.5}, {0.5, 0.5}};
  options.rolls_deg = {0.0, 30.0};
  options.offsets_m = {Eigen::Vector3d::Zero()};
  const auto plan = planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(),
                                       Eigen::Vector3d(0.2, 0.1, 1.0), cam.camera, cam.width, cam.height, options);
  ASSERT_EQ(plan.size(), 2u);
  const Eigen::Matrix3d R = plan[0].T_robot_head.linear().transpose() * plan[1].T_robot_head.linear();
  EXPECT_NEAR(Eigen::AngleAxisd(R).angle() * 180 / M_PI, 30.0, 1e-9);
}

TEST(IntrinsicsViewPlan, TheBoardCentreFromOneViewMatchesItsPose) {
  const calib::CameraCalibration cam = simCamera();
  const calib::AprilGrid grid;
  for (double yaw_deg : {0.0, 60.0, 95.0}) {
    Eigen::Isometry3d T_cam_board = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d centre = 1.2 * Eigen::Vector3d(std::sin(yaw_deg * M_PI / 180), 0.1, std::cos(yaw_deg * M_PI / 180));
    T_cam_board.linear() = Eigen::AngleAxisd(M_PI + yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_cam_board.translation() = centre - T_cam_board.linear() * Eigen::Vector3d(grid.width() / 2, grid.height() / 2, 0);
    const auto found = boardCentreInCamera(observe(grid, cam.camera, T_cam_board), grid, cam.camera);
    ASSERT_TRUE(found) << yaw_deg;
    EXPECT_LT((*found - centre).norm(), 1e-6) << yaw_deg;
  }
  EXPECT_FALSE(boardCentreInCamera(calib::TargetObservation{}, grid, cam.camera));
}

StereoSample sampleOf(const calib::TargetObservation& left, const calib::TargetObservation& right) {
  StereoSample s;
  s.views = {left, right};
  return s;
}

calib::TargetObservation gridAt(double x0, double y0, int n = 6) {
  calib::TargetObservation o;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      o.corner_ids.push_back(j * n + i);
      o.corners_px.emplace_back(x0 + 20.0 * i, y0 + 20.0 * j);
    }
  return o;
}

TEST(IntrinsicsCollector, KeepsStillNovelViewsAndRebuildsCoverageOnRemove) {
  const calib::CameraCalibration cam = simCamera();
  IntrinsicsCollector collector({cam.camera, cam.camera}, cam.width, cam.height);
  const StereoSample a = sampleOf(gridAt(900, 500), gridAt(880, 500));
  // No still before it: the stillness cannot be told.
  EXPECT_FALSE(collector.offer(a, nullptr).keep);
  // The still before moved 3 px: not kept, the reason says so with the number.
  const StereoSample a_moved = sampleOf(gridAt(897, 500), gridAt(877, 500));
  SampleVerdict v = collector.offer(a, &a_moved);
  EXPECT_FALSE(v.keep);
  EXPECT_NE(v.reason.find("moving: 3.00 px"), std::string::npos) << v.reason;
  // Still: kept; the same view again is too similar.
  EXPECT_TRUE(collector.offer(a, &a).keep);
  v = collector.offer(a, &a);
  EXPECT_FALSE(v.keep);
  EXPECT_NE(v.reason.find("too similar"), std::string::npos) << v.reason;
  // Only the right camera sees the board: kept (it is new there); the left view is unusable.
  const StereoSample right_only = sampleOf(calib::TargetObservation{}, gridAt(100, 100));
  EXPECT_TRUE(collector.offer(right_only, &right_only).keep);
  EXPECT_EQ(collector.samples().size(), 2u);
  EXPECT_EQ(collector.jointViews(), 1);
  const auto views = collector.cameraViews("eucm");
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0].model, "eucm");
  ASSERT_EQ(views[0].views.size(), 2u);
  EXPECT_TRUE(views[0].views[1].empty());
  EXPECT_EQ(views[1].views[1].corner_ids.size(), 36u);
  EXPECT_EQ(collector.coverage(1).polarBinsReached() > collector.coverage(0).polarBinsReached(), true);
  collector.remove(1);
  EXPECT_EQ(collector.samples().size(), 1u);
  int corners = 0;
  for (int r = 0; r < collector.coverage(1).gridRows(); ++r)
    for (int c = 0; c < collector.coverage(1).gridCols(); ++c) corners += collector.coverage(1).cellCount(c, r);
  EXPECT_EQ(corners, 36);
}

TEST(IntrinsicsDoneRule, EachUnmetCheckIsNamedWithItsNumber) {
  const calib::CameraCalibration cam = simCamera();
  IntrinsicsDoneRule rule;
  calib::ViewCoverage left(cam.camera, cam.width, cam.height), right(cam.camera, cam.width, cam.height);
  // Required: the bins that hold at least 2 % of the image; the rim bins of a 16:9 image do not.
  const std::vector<int> required = requiredPolarBins(left, rule);
  ASSERT_FALSE(required.empty());
  EXPECT_EQ(required.front(), 0);
  EXPECT_LT(required.size(), std::size_t(left.polarBins()));
  EXPECT_LT(left.imageShare(0), rule.min_bin_image_share);  // the centre disc is small, and required
  EXPECT_GE(left.imageShare(required.back()), rule.min_bin_image_share);
  for (int b = int(required.size()); b < left.polarBins(); ++b) EXPECT_LT(left.imageShare(b), rule.min_bin_image_share);
  DoneCheck check = checkCollection(5, {&left, &right}, rule);
  ASSERT_EQ(check.unmet.size(), 3u);
  EXPECT_EQ(check.unmet[0], "5 of 20 views");
  EXPECT_NE(check.unmet[1].find("cam_l: no corner yet at polar angles 0–10°"), std::string::npos) << check.unmet[1];
  // Corners in every required bin (one per bin, on the horizontal through the centre).
  calib::TargetObservation rays;
  for (int b : required) {
    const double a = (b + 0.5) * left.polarBinDeg() * M_PI / 180;
    Eigen::Vector2d px;
    ASSERT_TRUE(cam.camera.project(Eigen::Vector3d(std::sin(a), 0, std::cos(a)), px)) << b;
    if (px.x() > cam.width - 1) {  // beyond the image's side: along the diagonal instead
      ASSERT_TRUE(cam.camera.project(Eigen::Vector3d(std::sin(a) * 0.87, std::sin(a) * 0.49, std::cos(a)), px)) << b;
    }
    rays.corner_ids.push_back(b);
    rays.corners_px.push_back(px);
  }
  left.add(rays);
  right.add(rays);
  check = checkCollection(20, {&left, &right}, rule);
  EXPECT_TRUE(check.done()) << check.describe();

  // After the solve: σ, RMS, degeneracy.
  calib::IntrinsicResult result;
  calib::CameraIntrinsicResult c(cam);
  c.rms_px = 0.3;
  c.param_stddev = {0.1, 0.1, 0.1, 0.1, 1e-4, 1e-4};
  result.cameras.push_back(c);
  EXPECT_TRUE(checkSolve(result, rule).done());
  const double fx = cam.camera.params()[0];
  result.cameras[0].param_stddev[1] = 0.003 * fx;  // σ(fy) 0.3 % of f: above 0.2 %
  result.cameras[0].param_stddev[2] = 0.002 * cam.width;  // σ(cx) 0.2 % of the width: above 0.1 %
  result.cameras[0].rms_px = 1.5;
  result.cameras[0].degeneracy_warning = "fx trades off against xi";
  check = checkSolve(result, rule);
  ASSERT_EQ(check.unmet.size(), 4u) << check.describe();
  EXPECT_NE(check.describe().find("σ(fy)"), std::string::npos);
  EXPECT_NE(check.describe().find("σ(cx)"), std::string::npos);
  EXPECT_NE(check.describe().find("RMS 1.500 px"), std::string::npos);
  EXPECT_NE(check.describe().find("fx trades off"), std::string::npos);
  result.cameras[0].param_stddev.clear();
  EXPECT_NE(checkSolve(result, rule).describe().find("rank deficient"), std::string::npos);
  EXPECT_NE(rule.describe(10).find("20 views"), std::string::npos);
}

TEST(IntrinsicsProcedure, TheGenericGuessIsAFisheyeOfAbout200Degrees) {
  for (const char* model : {"ds", "eucm", "kb4"}) {
    const calib::GenericCamera guess = genericFisheye(model, 1920, 1080);
    EXPECT_EQ(guess.modelName(), model);
    EXPECT_NEAR(calib::polarAngleDeg(guess, Eigen::Vector2d(0, 539.5)), 100.0, 12.0) << model;
  }
}

// --- hand-eye ---

/// A still with the wrist marker 0.5 m ahead of both cameras, both arms' poses and joint states
/// bracketing the capture time.
link::proto::CalibrationStill markerStill(const calib::CameraCalibration& camera, bool with_marker = true) {
  link::proto::CalibrationStill still;
  still.set_sequence(9);
  still.set_capture_ns(1'000'000'000);
  still.set_joints_before_ns(995'000'000);
  still.set_joints_after_ns(1'005'000'000);
  still.set_manipulator_before_ns(992'000'000);
  still.set_manipulator_after_ns(1'002'000'000);
  for (int i = 0; i < 6; ++i) {
    still.add_head_joints(0.1 * i);
    still.add_manipulator_joints(-0.1 * i);
  }
  link::toLinkPose(calib::synthetic::poseOf({0.1, 0.2, 0.3}, {0.4, 0.0, 0.45}), still.mutable_t_robot_flange());
  link::toLinkPose(calib::synthetic::poseOf({0.0, 0.5, 0.0}, {0.3, 0.1, 0.6}), still.mutable_t_mount_wrist());
  const Eigen::Isometry3d T_cam_marker = calib::synthetic::poseOf({M_PI, 0.2, 0.0}, {0.05, 0.02, 0.5});
  for (auto* image : {still.mutable_left(), still.mutable_right()}) {
    const calib::GrayImage g =
        with_marker ? calib::renderTarget(camera.camera, camera.width, camera.height, T_cam_marker,
                                          calib::arucoMarkerTexture("DICT_4X4_50", 0, 0.1))
                    : calib::GrayImage(camera.width, camera.height);
    image->set_width(std::uint32_t(g.width));
    image->set_height(std::uint32_t(g.height));
    image->set_gray8(std::string(g.pixels.begin(), g.pixels.end()));
  }
  return still;
}

TEST(HandEyeSample, MarkerCornersAndBothArmsPosesOrTheReasonWhyNot) {
  const calib::CameraCalibration camera = simCamera(960, 540);
  const WristMarker marker;
  std::string reason;
  const auto sample = handEyeSampleOf(markerStill(camera), marker, &reason);
  ASSERT_TRUE(sample) << reason;
  EXPECT_EQ(sample->width, 960);
  ASSERT_TRUE(sample->sample.corners_l && sample->sample.corners_r);
  // The corners where the camera model puts them (the detector is sub-pixel).
  const Eigen::Isometry3d T_cam_marker = calib::synthetic::poseOf({M_PI, 0.2, 0.0}, {0.05, 0.02, 0.5});
  const auto corners3 = calib::markerCorners(0.1);
  for (std::size_t k = 0; k < 4; ++k) {
    Eigen::Vector2d px;
    ASSERT_TRUE(camera.camera.project(T_cam_marker * corners3[k], px));
    EXPECT_LT(((*sample->sample.corners_l)[k] - px).norm(), 0.5) << k;
  }
  EXPECT_TRUE(sample->sample.T_mount_wrist.isApprox(calib::synthetic::poseOf({0.0, 0.5, 0.0}, {0.3, 0.1, 0.6}), 1e-9));
  EXPECT_EQ(sample->thumbnails[0].width, 160);

  auto no_manipulator = markerStill(camera);
  no_manipulator.clear_manipulator_joints();
  EXPECT_FALSE(handEyeSampleOf(no_manipulator, marker, &reason));
  EXPECT_NE(reason.find("no manipulator joints"), std::string::npos) << reason;
  auto unbracketed = markerStill(camera);
  unbracketed.set_manipulator_after_ns(999'000'000);  // the newest report is before the capture
  EXPECT_FALSE(handEyeSampleOf(unbracketed, marker, &reason));
  EXPECT_NE(reason.find("manipulator's joint states do not bracket"), std::string::npos) << reason;
  auto gap = markerStill(camera);
  gap.set_joints_after_ns(1'030'000'000);  // 35 ms: reports were lost
  EXPECT_FALSE(handEyeSampleOf(gap, marker, &reason));
  EXPECT_NE(reason.find("head arm's joint states around the capture time are 35 ms apart"), std::string::npos) << reason;
  EXPECT_FALSE(handEyeSampleOf(markerStill(camera, false), marker, &reason));
  EXPECT_NE(reason.find("in neither image"), std::string::npos) << reason;
  WristMarker other = marker;
  other.id = 3;
  EXPECT_FALSE(handEyeSampleOf(markerStill(camera), other, &reason));
}

calib::SystemCalibration handEyeCameras() {
  calib::SystemCalibration system;
  system.cameras.push_back({"cam_l", calib::synthetic::lens1280(false).camera, 1280, 1024});
  system.cameras.push_back({"cam_r", calib::synthetic::lens1280(true).camera, 1280, 1024});
  system.T_cam_l_cam_r = calib::synthetic::trueTCamLCamR();
  return system;
}

HandEyeStillSample stillSample(const calib::HandEyeSample& s) {
  HandEyeStillSample h;
  h.sample = s;
  h.width = 1280;
  h.height = 1024;
  return h;
}

TEST(HandEyeCollector, GatesNearDuplicatesSolvesFromFiveMarksOutliersAndStatesTheRule) {
  const auto truth = calib::synthetic::handEyeTruth();
  auto samples = calib::synthetic::simulateHandEyeSession(truth, calib::synthetic::lens1280(false), calib::synthetic::lens1280(true),
                                              calib::synthetic::trueTCamLCamR(), 0.1, 40, 0.2, 21);
  ASSERT_EQ(samples.size(), 40u);
  HandEyeCollectorOptions options;
  options.rule.min_samples = 20;
  HandEyeCollector c(handEyeCameras(), WristMarker{}, options);
  std::string reason;
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(c.offer(stillSample(samples[std::size_t(i)]), &reason)) << reason;
  // The same poses again (a still taken before anything moved) add nothing.
  EXPECT_FALSE(c.offer(stillSample(samples[2]), &reason));
  EXPECT_NE(reason.find("too close to sample 3"), std::string::npos) << reason;
  std::string error;
  EXPECT_FALSE(c.solve(&error));
  EXPECT_NE(error.find("only 4 samples"), std::string::npos) << error;
  auto check = c.check();
  ASSERT_FALSE(check.done());
  EXPECT_NE(check.describe().find("4 of 20 samples"), std::string::npos) << check.describe();
  EXPECT_NE(check.describe().find("no solution yet"), std::string::npos) << check.describe();

  // One sample's left corners 12 px off: marked as the outlier, removed, the rest fits.
  samples[9].corners_l->at(0) += Eigen::Vector2d(12.0, 0.0);
  samples[9].corners_l->at(2) += Eigen::Vector2d(-12.0, 6.0);
  for (std::size_t i = 4; i < 40; ++i) ASSERT_TRUE(c.offer(stillSample(samples[i]), &reason)) << i << ": " << reason;
  ASSERT_TRUE(c.solve(&error)) << error;
  const std::vector<bool> outliers = c.outliers();
  EXPECT_EQ(std::count(outliers.begin(), outliers.end(), true), 1);
  EXPECT_TRUE(outliers[9]);
  EXPECT_EQ(c.removeOutliers(), 1);
  ASSERT_TRUE(c.solve(&error)) << error;
  check = c.check();
  EXPECT_TRUE(check.done()) << check.describe();
  const auto diversity = c.diversity();
  EXPECT_GT(diversity.head_axis_spread_deg, 10.0);
  EXPECT_GT(diversity.wrist_axis_spread_deg, 10.0);
  const auto out = c.calibration();
  ASSERT_TRUE(out && out->T_robot_mount);
  EXPECT_LT((out->T_flange_cam_l->translation() - truth.T_flange_cam_l.translation()).norm(), 2e-3);

  // A rule it cannot meet names the number it measured.
  HandEyeCollectorOptions strict = options;
  strict.rule.max_translation_std_mm = 1e-4;
  HandEyeCollector c2(handEyeCameras(), WristMarker{}, strict);
  for (std::size_t i = 0; i < 20; ++i) ASSERT_TRUE(c2.offer(stillSample(samples[i + 10]), &reason));
  ASSERT_TRUE(c2.solve(&error)) << error;
  EXPECT_NE(c2.check().describe().find("T_flange_cam_l: |σ_t|"), std::string::npos) << c2.check().describe();
}

TEST(HandEyeCollector, RotationsAboutOneAxisAreRefusedAsDegenerate) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, calib::synthetic::lens1280(false), calib::synthetic::lens1280(true),
                                                    calib::synthetic::trueTCamLCamR(), 0.1, 20, 0.2, 22, /*head_two_axes=*/false);
  HandEyeCollector c(handEyeCameras(), WristMarker{});
  std::string reason, error;
  for (const auto& s : samples) c.offer(stillSample(s), &reason);
  ASSERT_GE(c.samples().size(), 15u);
  EXPECT_FALSE(c.solve(&error));
  EXPECT_NE(error.find("head arm's rotations do not separate"), std::string::npos) << error;
  EXPECT_FALSE(c.result());
  EXPECT_FALSE(c.calibration());
  EXPECT_NE(c.check().describe().find("rotation axes spread: head"), std::string::npos) << c.check().describe();
}

// Applying live: only what a wizard measured replaces the calibration in use, and the change is
// stated in mm, ° and image px (the same calibration at another resolution moves nothing).
TEST(CalibrationChange, OnlyTheMeasuredPartIsAppliedAndTheChangeIsMeasured) {
  auto loaded = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  ASSERT_TRUE(loaded);
  const calib::SystemCalibration in_use = *loaded;

  calib::SystemCalibration result = in_use;
  result.T_flange_cam_l->translation().x() += 0.012;
  Eigen::VectorXd p = result.cameras[1].camera.params();
  p[2] += 2.0;  // cx: the right image moves 2 px sideways
  result.cameras[1].camera = *calib::GenericCamera::create(result.cameras[1].camera.modelName(), p);

  const calib::SystemCalibration cameras = withMeasured(in_use, result, MeasuredParts::kCameras);
  EXPECT_TRUE(cameras.T_flange_cam_l->isApprox(*in_use.T_flange_cam_l)) << "a camera result keeps the hand-eye";
  EXPECT_EQ(cameras.cameras[1].camera.params(), p);
  const calib::SystemCalibration hand_eye = withMeasured(in_use, result, MeasuredParts::kHandEye);
  EXPECT_TRUE(hand_eye.T_flange_cam_l->isApprox(*result.T_flange_cam_l));
  EXPECT_EQ(hand_eye.cameras[1].camera.params(), in_use.cameras[1].camera.params()) << "a hand-eye result keeps the cameras";

  const auto find = [](const std::vector<CalibrationDifference>& ds, const std::string& what) {
    for (const auto& d : ds)
      if (d.what == what) return d;
    ADD_FAILURE() << "no row " << what;
    return CalibrationDifference{};
  };
  const auto none = differences(in_use, in_use);
  for (const auto& d : none) EXPECT_LT(d.value, 1e-9) << d.what;
  EXPECT_FALSE(find(none, "cam_l image").detail.empty());

  const auto both = differences(in_use, result);
  EXPECT_NEAR(find(both, "T_flange_cam_l translation").value, 12.0, 1e-9);
  EXPECT_NEAR(find(both, "T_flange_cam_l rotation").value, 0.0, 1e-9);
  EXPECT_NEAR(find(both, "cam_r image").value, 2.0, 1e-6) << find(both, "cam_r image").detail;
  EXPECT_LT(find(both, "cam_l image").value, 1e-9);

  // The same cameras calibrated at half the resolution: nothing moves.
  calib::SystemCalibration half = in_use;
  std::string error;
  for (auto& camera : half.cameras) camera = *calib::atResolution(camera, camera.width / 2, camera.height / 2, &error);
  EXPECT_LT(find(differences(in_use, half), "cam_l image").value, 1e-6);
}

}  // namespace
}  // namespace telesphere::console::calibration
