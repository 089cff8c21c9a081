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

}  // namespace
}  // namespace telesphere::console::calibration
