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
    behind.fallbacks = 0;
    EXPECT_TRUE(planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.01, 0, -1),
                                   cam.camera, cam.width, cam.height, behind).empty());
    behind.max_turn_deg = 180.0;
    EXPECT_EQ(planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.01, 0, -1),
                                 cam.camera, cam.width, cam.height, behind).size(), 1u);
  }
  EXPECT_GT(beyond_90, 20 * 4);  // the rim targets lie beyond 90° off axis
  // A target outside the model's domain (the image's extreme corner) is left out.
  options.targets = {{0.0, 0.0}, {0.5, 0.5}};
  options.fallbacks = 0;
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
  options.fallbacks = 0;
  const auto plan = planIntrinsicViews(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(),
                                       Eigen::Vector3d(0.2, 0.1, 1.0), cam.camera, cam.width, cam.height, options);
  ASSERT_EQ(plan.size(), 2u);
  const Eigen::Matrix3d R = plan[0].T_robot_head.linear().transpose() * plan[1].T_robot_head.linear();
  EXPECT_NEAR(Eigen::AngleAxisd(R).angle() * 180 / M_PI, 30.0, 1e-9);
}

// The arm refuses some poses, depending on where it stands (console_calibrate_test lost up to 10
// of 29 targets, among them the image corners that give the widest polar bin). Each target's
// first pose is followed by other poses that show the board centre on the same pixel: the next
// rolls, then the next head offsets, none the same as another.
TEST(IntrinsicsViewPlan, EachTargetHasOtherPosesThatShowTheBoardOnTheSamePixel) {
  const calib::CameraCalibration cam = simCamera();
  ViewPlanOptions options;
  options.targets = ViewPlanOptions::outerTargets();
  ASSERT_EQ(options.fallbacks, 4);
  Eigen::Isometry3d T_robot_head0 = Eigen::Isometry3d::Identity();
  T_robot_head0.translation() = Eigen::Vector3d(0.4, 0, 0.45);
  Eigen::Isometry3d T_head_cam = Eigen::Isometry3d::Identity();
  T_head_cam.translation() = Eigen::Vector3d(-0.03, 0.06, 0.05);
  const Eigen::Vector3d p_robot_board = (T_robot_head0 * T_head_cam) * Eigen::Vector3d(0.1, -0.05, 1.2);
  const auto plan = planIntrinsicViews(T_robot_head0, T_head_cam, p_robot_board, cam.camera, cam.width, cam.height, options);
  std::vector<std::vector<const PlannedView*>> per_target(options.targets.size());
  int previous_target = -1;
  for (const PlannedView& view : plan) {
    ASSERT_GE(view.target, previous_target) << "a target's poses follow each other, in target order";
    ASSERT_EQ(view.fallback, view.target == previous_target) << "the first pose of a target is not a fallback";
    previous_target = view.target;
    per_target[std::size_t(view.target)].push_back(&view);
    Eigen::Vector2d px;
    ASSERT_TRUE(cam.camera.project((view.T_robot_head * T_head_cam).inverse() * p_robot_board, px));
    EXPECT_LT((px - view.target_px).norm(), 1e-6) << view.target << (view.fallback ? " (fallback)" : "");
    const Eigen::Vector2d want(options.targets[std::size_t(view.target)].x() * (cam.width - 1),
                               options.targets[std::size_t(view.target)].y() * (cam.height - 1));
    EXPECT_LT((view.target_px - want).norm(), 1e-9);
  }
  for (std::size_t t = 0; t < per_target.size(); ++t) {
    const auto& poses = per_target[t];
    ASSERT_EQ(poses.size(), 5u) << "target " << t << ": its pose and 4 fallbacks";
    // The first pose is the one a plan without fallbacks has (roll t % 3, offset t % 3).
    EXPECT_EQ(poses[0]->roll_deg, options.rolls_deg[t % 3]);
    EXPECT_LT((poses[0]->T_robot_head.translation() - T_robot_head0.translation() - options.offsets_m[t % 3]).norm(), 1e-12);
    // Fallbacks 1 and 2 roll the other ways at the same head position; 3 and 4 move the head.
    EXPECT_NE(poses[1]->roll_deg, poses[0]->roll_deg);
    EXPECT_NE(poses[2]->roll_deg, poses[0]->roll_deg);
    EXPECT_NE(poses[2]->roll_deg, poses[1]->roll_deg);
    EXPECT_LT((poses[1]->T_robot_head.translation() - poses[0]->T_robot_head.translation()).norm(), 1e-12);
    EXPECT_GT((poses[3]->T_robot_head.translation() - poses[0]->T_robot_head.translation()).norm(), 0.05);
    for (std::size_t a = 0; a < poses.size(); ++a)
      for (std::size_t b = a + 1; b < poses.size(); ++b)
        EXPECT_FALSE(poses[a]->T_robot_head.isApprox(poses[b]->T_robot_head, 1e-9)) << t << ": poses " << a << " and " << b;
  }
  // Without fallbacks, one pose per target, as before.
  options.fallbacks = 0;
  EXPECT_EQ(planIntrinsicViews(T_robot_head0, T_head_cam, p_robot_board, cam.camera, cam.width, cam.height, options).size(),
            options.targets.size());
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

// console_calibrate_test failed in CI (and 3 of 5 Release runs here) on "cam_l: no corner yet at
// polar angles 100–110°": its robot renders 1280×720, where an 8.8 cm tag 1.21 m away spans
// 16.7 px radially at 105° in cam_l (4.00 px a degree: the rim is squeezed), under 2 px for each
// of a tag's 10 cells; the stills near the corners read 0–8 tags of ~20 in view. The rule asks only
// for bins where a tag can be read; at 1920×1080, or with the board nearer, it asks for 100–110°.
TEST(IntrinsicsDoneRule, RimBinsWhereTheBoardsTagsAreTooSmallToReadAreNotRequired) {
  const auto truth = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/tests/console/data/calibration_truth.yaml");
  ASSERT_TRUE(truth);
  const auto cameraAt = [&](int camera, int width, int height) {
    std::string error;
    const auto c = calib::atResolution(truth->cameras[std::size_t(camera)], width, height, &error);
    EXPECT_TRUE(c) << error;
    return c->camera;
  };
  const calib::GenericCamera cam_l_720 = cameraAt(0, 1280, 720), cam_r_720 = cameraAt(1, 1280, 720),
                             cam_l_1080 = cameraAt(0, 1920, 1080);
  IntrinsicsDoneRule rule;
  const double tag_deg = 2.0 * std::atan(0.5 * 0.088 / 1.21) * 180.0 / M_PI;  // 4.17°
  const calib::ViewCoverage left_720(cam_l_720, 1280, 720), right_720(cam_r_720, 1280, 720),
      left_1080(cam_l_1080, 1920, 1080);
  // The radial scale in a bin's middle against the model along the horizontal (an isotropic
  // lens: the largest over the azimuths is within a few % of it).
  for (const auto& [cov, cam] : {std::pair{&left_720, &cam_l_720}, std::pair{&left_1080, &cam_l_1080}})
    for (int b : {0, 5, 9, 10}) {
      const double a = (b + 0.5) * 10.0 * M_PI / 180.0, da = 1e-4;
      Eigen::Vector2d p0, p1;
      ASSERT_TRUE(cam->project(Eigen::Vector3d(-std::sin(a), 0, std::cos(a)), p0));
      ASSERT_TRUE(cam->project(Eigen::Vector3d(-std::sin(a + da), 0, std::cos(a + da)), p1));
      const double numeric = (p1 - p0).norm() / (da * 180.0 / M_PI);
      EXPECT_NEAR(cov->radialPxPerDeg(b), numeric, 0.05 * numeric) << "bin " << b;
    }
  EXPECT_NEAR(left_720.radialPxPerDeg(10), 4.00, 0.05);
  EXPECT_NEAR(right_720.radialPxPerDeg(10), 5.30, 0.05);
  // Without the tag angle: the share alone (100–110° holds 5 % of cam_l's image).
  EXPECT_EQ(requiredPolarBins(left_720, rule).back(), 10);
  EXPECT_TRUE(unreadablePolarBins(left_720, rule).empty());
  // With the board 1.21 m away: cam_l's 100–110° ring is optional at 1280×720 and named as such;
  // cam_r (5.30 px a degree there: 22 px a tag) and cam_l at 1920×1080 (25 px) still need it.
  rule.tag_angle_deg = tag_deg;
  EXPECT_EQ(requiredPolarBins(left_720, rule).back(), 9);
  EXPECT_EQ(unreadablePolarBins(left_720, rule), std::vector<int>{10});
  EXPECT_EQ(requiredPolarBins(right_720, rule).back(), 10);
  EXPECT_EQ(requiredPolarBins(left_1080, rule).back(), 10);
  EXPECT_TRUE(unreadablePolarBins(left_1080, rule).empty());
  // The board at 0.8 m: tags 6.3° across (25 px), readable there again.
  rule.tag_angle_deg = 2.0 * std::atan(0.5 * 0.088 / 0.8) * 180.0 / M_PI;
  EXPECT_EQ(requiredPolarBins(left_720, rule).back(), 10);
  // The collector carries the board's tag angle into the rule the procedure checks.
  IntrinsicsCollector collector({cam_l_720, cam_r_720}, 1280, 720);
  EXPECT_EQ(ruleInEffect(IntrinsicsDoneRule{}, collector).tag_angle_deg, 0.0);
  collector.setTagAngleDeg(tag_deg);
  EXPECT_EQ(ruleInEffect(IntrinsicsDoneRule{}, collector).tag_angle_deg, tag_deg);
  EXPECT_EQ(missingPolarBins(collector.coverage(0), ruleInEffect(IntrinsicsDoneRule{}, collector)).back(), 9);
  EXPECT_NE(IntrinsicsDoneRule{}.describe(10).find("tags span ≥ 2 px a cell"), std::string::npos);
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
