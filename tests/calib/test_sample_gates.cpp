// SPDX-License-Identifier: MIT
/// @brief The calibration wizard's gates and coverage (calib/sample_gates.h, view_coverage.h):
///        each gate at and beyond its bound with the number in its reason; coverage of a real
///        fisheye model (the simulated >180° cameras) in grid cells and polar bins to the rim,
///        the polar angle against the model's own projection, views at the centre only never
///        reaching the rim bins.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "calib/calibration_file.h"
#include "calib/sample_gates.h"
#include "calib/view_coverage.h"

namespace telesphere::calib {
namespace {

/// A 6×6 grid of corners (ids 0…35) `step` px apart from (x0, y0).
TargetObservation grid(double x0, double y0, double step = 20.0, int n = 6) {
  TargetObservation o;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      o.corner_ids.push_back(j * n + i);
      o.corners_px.emplace_back(x0 + i * step, y0 + j * step);
    }
  return o;
}

TEST(SampleGates, EachGateAtItsBoundWithItsNumber) {
  const SampleGateOptions options;  // 24 corners, 0.5 px still, 20 px novelty
  const TargetObservation view = grid(100, 100);
  TargetObservation still = grid(100.4, 100);  // 0.4 px: still
  EXPECT_TRUE(judgeView(view, &still, {}, options).keep());
  EXPECT_EQ(judgeView(view, &still, {}, options).reason, "keep");
  EXPECT_TRUE(std::isinf(judgeView(view, &still, {}, options).novelty_px));  // nothing kept yet
  // Moving: 0.6 px since the still before.
  const TargetObservation moved = grid(100.6, 100);
  const GateResult moving = judgeView(view, &moved, {}, options);
  EXPECT_EQ(moving.verdict, GateVerdict::kMoving);
  EXPECT_NEAR(moving.motion_px, 0.6, 1e-9);
  EXPECT_NE(moving.reason.find("0.60 px"), std::string::npos) << moving.reason;
  // No still before, or one sharing too few corners.
  EXPECT_EQ(judgeView(view, nullptr, {}, options).verdict, GateVerdict::kNoPreviousView);
  TargetObservation other = grid(100, 100, 20.0, 1);  // one shared corner
  EXPECT_EQ(judgeView(view, &other, {}, options).verdict, GateVerdict::kMoving);
  // Too few corners: 23 of 24.
  TargetObservation sparse = view;
  sparse.corner_ids.resize(23);
  sparse.corners_px.resize(23);
  const GateResult few = judgeView(sparse, &still, {}, options);
  EXPECT_EQ(few.verdict, GateVerdict::kTooFewCorners);
  EXPECT_EQ(few.reason, "23 corners (24 needed)");
  // Too similar to a kept view: 19 px away; 21 px is new enough; the closest kept view counts.
  const GateResult similar = judgeView(view, &still, {grid(300, 300), grid(119, 100)}, options);
  EXPECT_EQ(similar.verdict, GateVerdict::kTooSimilar);
  EXPECT_NEAR(similar.novelty_px, 19.0, 1e-9);
  EXPECT_TRUE(judgeView(view, &still, {grid(121, 100)}, options).keep());
  // A kept view sharing no corner is no reason to refuse.
  TargetObservation disjoint = grid(100, 100);
  for (int& id : disjoint.corner_ids) id += 100;
  EXPECT_TRUE(judgeView(view, &still, {disjoint}, options).keep());
}

TEST(SampleGates, MedianMotionIgnoresAFewOutlierCorners) {
  TargetObservation a = grid(0, 0), b = grid(0.1, 0);
  b.corners_px[0].x() += 50;  // one misdetected corner
  b.corners_px[1].x() += 50;
  EXPECT_NEAR(medianCornerMotion(a, b, 4), 0.1, 1e-9);
  EXPECT_GT(meanCornerDisplacement(a, b, 4), 2.0);
  EXPECT_TRUE(std::isnan(medianCornerMotion(a, grid(0, 0, 20.0, 1), 4)));
  EXPECT_NEAR(medianCornerMotion(grid(0, 0, 20, 2), grid(1, 0, 20, 2), 4), 1.0, 1e-12);  // even count
}

TEST(ViewCoverage, AFisheyeBeyond180DegreesIsCoveredToItsRimInPolarBins) {
  auto calibration = loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  ASSERT_TRUE(calibration) << calibration.error().describe();
  const CameraCalibration& cam = calibration->cameras[0];
  ViewCoverage coverage(cam.camera, cam.width, cam.height);
  // The simulated lens sees beyond 180° (more than 90° off axis) somewhere in its image.
  EXPECT_GT(coverage.imageMaxPolarDeg(), 90.0);
  EXPECT_EQ(coverage.polarBins(), int(std::ceil(std::min(coverage.imageMaxPolarDeg(),
                                                         cam.camera.maxAngle() * 180 / M_PI) / 10.0 - 1e-9)));
  // The polar angle agrees with the model's own projection of known rays (round trip).
  for (double deg : {0.0, 30.0, 60.0, 89.0, 95.0}) {
    const double a = deg * M_PI / 180;
    Eigen::Vector2d px;
    if (!cam.camera.project(Eigen::Vector3d(std::sin(a), 0, std::cos(a)), px)) continue;
    EXPECT_NEAR(polarAngleDeg(cam.camera, px), deg, 1e-6) << deg;
  }
  // Views near the centre fill the inner bins only; the wizard must ask for the rim.
  const Eigen::Vector2d c(cam.width / 2.0, cam.height / 2.0);
  coverage.add(grid(c.x() - 50, c.y() - 50));
  EXPECT_LE(coverage.polarBinsReached(), 2);
  EXPECT_LT(coverage.gridCoverage(), 0.2);
  // Seeded views spread over the whole image reach every bin and every cell.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int v = 0; v < 400; ++v)
    coverage.add(grid(u(rng) * (cam.width - 60), u(rng) * (cam.height - 60), 10.0, 6));
  // The widest angles lie in the image's corners, which random views rarely reach: add them.
  for (double x : {0.0, cam.width - 51.0})
    for (double y : {0.0, cam.height - 51.0}) coverage.add(grid(x, y, 10.0, 6));
  EXPECT_EQ(coverage.gridCoverage(), 1.0);
  for (int b = 0; b < coverage.polarBins(); ++b) {
    // Bins whose ring lies wholly outside the image can stay empty; every other one is reached.
    if (b * coverage.polarBinDeg() < coverage.imageMaxPolarDeg() - 1.0) {
      EXPECT_GT(coverage.polarCount(b), 0) << b;
    }
  }
  EXPECT_NE(coverage.describe().find("polar bins"), std::string::npos);
  // Each bin's share of the image: the first bin is the disc within 10° of the axis (its radius
  // from projecting a 10° ray), and the rim bins hold only the image's corners.
  Eigen::Vector2d px10;
  ASSERT_TRUE(cam.camera.project(Eigen::Vector3d(std::sin(10 * M_PI / 180), 0, std::cos(10 * M_PI / 180)), px10));
  const double r10 = px10.x() - cam.camera.params()[2];
  EXPECT_NEAR(coverage.imageShare(0), M_PI * r10 * r10 / (double(cam.width) * cam.height), 0.002);
  double total = 0;
  for (int b = 0; b < coverage.polarBins(); ++b) total += coverage.imageShare(b);
  EXPECT_GT(total, 0.95);
  EXPECT_LE(total, 1.0 + 1e-12);
  EXPECT_LT(coverage.imageShare(coverage.polarBins() - 1), 0.01);
  // Corners outside the image are not counted; clear() empties.
  TargetObservation outside;
  outside.corner_ids = {0};
  outside.corners_px = {Eigen::Vector2d(-10, -10)};
  coverage.clear();
  coverage.add(outside);
  EXPECT_EQ(coverage.gridCoverage(), 0.0);
  EXPECT_EQ(coverage.polarBinsReached(), 0);
}

}  // namespace
}  // namespace telesphere::calib
