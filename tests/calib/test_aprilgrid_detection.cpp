// SPDX-License-Identifier: MIT
/// @brief Aprilgrid description, rendering and detection on images of the >180° lens: corners
///        found where the true model projects them, with kalibr's corner numbering; the hand-eye
///        marker's corners without the bias cornerSubPix has at L-shaped corners.
#include <gtest/gtest.h>

#include "calib/aprilgrid.h"
#include "calib/marker_edge_corners.h"
#include "calib/target_detection.h"
#include "calib/target_render.h"
#include "calib/synthetic/calibration_sessions.h"
#include "calib/synthetic/marker_views.h"

namespace telesphere::calib {
namespace {

using calib::synthetic::lens1280;
using calib::synthetic::testGrid;
using calib::synthetic::markerCornerErrors;
using calib::synthetic::MarkerCornerErrors;
using calib::synthetic::markerPoseFacing;
using calib::synthetic::randomMarkerPosesFacing;

TEST(AprilGrid, KalibrCornerKIsOpenCvCornerOneMinusKModFour) {
  EXPECT_EQ(kalibrToOpenCvCorner(0), 1);
  EXPECT_EQ(kalibrToOpenCvCorner(1), 0);
  EXPECT_EQ(kalibrToOpenCvCorner(2), 3);
  EXPECT_EQ(kalibrToOpenCvCorner(3), 2);
}

TEST(AprilGrid, CornerGeometryFollowsKalibr) {
  const AprilGrid grid{6, 5, 0.1, 0.3};
  EXPECT_TRUE(grid.cornerPosition(0).isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(grid.cornerPosition(1).isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE(grid.cornerPosition(2).isApprox(Eigen::Vector3d(0.1, 0.1, 0)));
  EXPECT_TRUE(grid.cornerPosition(3).isApprox(Eigen::Vector3d(0, 0.1, 0)));
  // Tag 7 = row 1, column 1.
  EXPECT_TRUE(grid.cornerPosition(4 * 7).isApprox(Eigen::Vector3d(0.13, 0.13, 0)));
  EXPECT_NEAR(grid.width(), 6 * 0.13 - 0.03, 1e-12);
}

TEST(AprilGrid, ReadsKalibrTargetYaml) {
  const auto grid = parseAprilGrid(
      "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 7\ntagSize: 0.088\ntagSpacing: 0.3\n", "t.yaml");
  ASSERT_TRUE(grid) << grid.error().describe();
  EXPECT_EQ(grid->tag_cols, 6);
  EXPECT_EQ(grid->tag_rows, 7);
  EXPECT_DOUBLE_EQ(grid->tag_size, 0.088);
  const auto bad = parseAprilGrid("target_type: 'checkerboard'\n", "t.yaml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().field, "target_type");
  const auto negative = parseAprilGrid(
      "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: -1\ntagSpacing: 0.3\n", "t.yaml");
  ASSERT_FALSE(negative);
  EXPECT_EQ(negative.error().line, 4);
}

/// Detects the grid rendered at T_cam_board and compares every corner with the true projection
/// of the kalibr corner of the same id.
struct DetectionCheck {
  int corners = 0;
  double max_error_px = 0, rms_px = 0;
  TargetObservation obs;
};

DetectionCheck renderAndDetect(const Eigen::Isometry3d& T_cam_board) {
  const auto cam = lens1280();
  const AprilGrid grid = testGrid();
  const GrayImage image =
      renderTarget(cam.camera, cam.width, cam.height, T_cam_board, aprilGridTexture(grid));
  DetectionCheck out;
  out.obs = detectAprilGrid(image, grid);
  double sum2 = 0;
  for (std::size_t i = 0; i < out.obs.corner_ids.size(); ++i) {
    Eigen::Vector2d truth;
    EXPECT_TRUE(cam.camera.project(T_cam_board * grid.cornerPosition(out.obs.corner_ids[i]), truth));
    const double e = (truth - out.obs.corners_px[i]).norm();
    out.max_error_px = std::max(out.max_error_px, e);
    sum2 += e * e;
  }
  out.corners = static_cast<int>(out.obs.corner_ids.size());
  out.rms_px = out.corners ? std::sqrt(sum2 / out.corners) : INFINITY;
  return out;
}

TEST(AprilGridDetection, CornersMatchKalibrNumberingOnAxis) {
  const Eigen::Isometry3d T = calib::synthetic::boardPoseAt(testGrid(), 0.0, 0.0, 0.55, 0.2, -0.15, 0.1);
  const DetectionCheck check = renderAndDetect(T);
  EXPECT_GE(check.obs.tags_detected, 34);
  EXPECT_GE(check.corners, 136);
  // A wrong corner order would be off by a tag edge (tens of pixels).
  EXPECT_LT(check.max_error_px, 0.6);
  EXPECT_LT(check.rms_px, 0.25);
}

TEST(AprilGridDetection, TagZeroIsBottomLeftSeenFromTheFront) {
  const Eigen::Isometry3d T = calib::synthetic::boardPoseAt(testGrid(), 0.0, 0.0, 0.55, 0.0, 0.0, 0.0);
  const DetectionCheck check = renderAndDetect(T);
  ASSERT_GE(check.corners, 136);
  // Corner 0 (bottom-left of tag 0) lies below the top-left tag's and left of the
  // bottom-right tag's bottom-left corner in the image.
  const auto find = [&](int id) {
    const auto it = std::find(check.obs.corner_ids.begin(), check.obs.corner_ids.end(), id);
    EXPECT_NE(it, check.obs.corner_ids.end()) << "corner " << id;
    return check.obs.corners_px[static_cast<std::size_t>(it - check.obs.corner_ids.begin())];
  };
  const AprilGrid grid = testGrid();
  const Eigen::Vector2d c0 = find(0);
  EXPECT_GT(c0.y(), find(4 * (grid.numTags() - grid.tag_cols)).y() + 100);
  EXPECT_LT(c0.x(), find(4 * (grid.tag_cols - 1)).x() - 100);
}

TEST(AprilGridDetection, FindsTheBoardBeyondNinetyDegreesOffAxis) {
  // Board centre 82° off the optical axis, its far half beyond 90°: only a bearing-based
  // pipeline can use such a view.
  const Eigen::Isometry3d T = calib::synthetic::boardPoseAt(testGrid(), 82.0 * M_PI / 180, 0.0, 0.6, 0.0, 0.0, 0.0);
  const DetectionCheck check = renderAndDetect(T);
  EXPECT_GE(check.corners, 24);
  int behind = 0;
  const AprilGrid grid = testGrid();
  for (int id : check.obs.corner_ids) behind += (T * grid.cornerPosition(id)).z() < 0;
  EXPECT_GT(behind, 0) << "no corner detected beyond 90 deg of " << check.corners;
  EXPECT_LT(check.max_error_px, 1.0);
}

TEST(AprilGridDetection, TooFewTagsOrBorderCornersYieldNothing) {
  const auto cam = lens1280();
  const AprilGrid grid = testGrid();
  // Board far away and small: fewer tags than required.
  const GrayImage blank(cam.width, cam.height, 128);
  EXPECT_TRUE(detectAprilGrid(blank, grid).empty());
  const Eigen::Isometry3d T = calib::synthetic::boardPoseAt(grid, 0.0, 0.0, 0.55, 0.0, 0.0, 0.0);
  const GrayImage image = renderTarget(cam.camera, cam.width, cam.height, T, aprilGridTexture(grid));
  DetectionOptions strict;
  strict.min_tags = 37;
  EXPECT_TRUE(detectAprilGrid(image, grid, strict).empty());
  EXPECT_EQ(detectAprilGrid(image, grid, strict).tags_detected, 36);
  DetectionOptions wide_margin;
  wide_margin.border_margin_px = 500;  // only the image centre remains
  const auto obs = detectAprilGrid(image, grid, wide_margin);
  for (const auto& px : obs.corners_px) {
    EXPECT_GE(px.x(), 500);
    EXPECT_GE(px.y(), 500);
  }
  EXPECT_LT(obs.corner_ids.size(), detectAprilGrid(image, grid).corner_ids.size());
}

TEST(ArucoDetection, FindsTheHandEyeMarkerCorners) {
  const auto cam = lens1280();
  const double size = 0.1;
  const Eigen::Isometry3d T_cam_marker =
      calib::synthetic::poseOf(Eigen::Vector3d(M_PI + 0.3, 0.2, 0.4), Eigen::Vector3d(0.1, -0.05, 0.4));
  const GrayImage image = renderTarget(cam.camera, cam.width, cam.height, T_cam_marker,
                                       arucoMarkerTexture("DICT_4X4_50", 7, size));
  const auto corners = detectArucoMarker(image, "DICT_4X4_50", 7);
  ASSERT_TRUE(corners);
  const auto p = markerCorners(size);
  for (std::size_t k = 0; k < 4; ++k) {
    Eigen::Vector2d truth;
    ASSERT_TRUE(cam.camera.project(T_cam_marker * p[k], truth));
    EXPECT_LT(((*corners)[k] - truth).norm(), 0.6) << "corner " << k;
  }
  EXPECT_FALSE(detectArucoMarker(image, "DICT_4X4_50", 8));
  EXPECT_THROW(detectArucoMarker(image, "DICT_NOPE", 7), std::invalid_argument);
}

TEST(ArucoDetection, MarkerCornersFromTheEdgesAreUnbiasedWhereCornerSubPixShrinksTheMarker) {
  // The hand-eye marker as the head sees it: 0.45–0.8 m away, up to 40° off axis, tilted up to
  // 34°, any roll; and 60–85° off axis, towards the rim of the >180° lens, where its sides bend
  // most (OpenCV finds none at 90°).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const std::vector<Eigen::Isometry3d> poses = randomMarkerPosesFacing(24, 0, 40, rng);
  std::vector<Eigen::Isometry3d> rim;
  for (int i = 0; i < 6; ++i) {
    const double axis = 2 * M_PI * u(rng), roll = 2 * M_PI * u(rng);
    rim.push_back(markerPoseFacing(0.5, (60.0 + 5.0 * i) * M_PI / 180, M_PI * (i % 2), 0.3, axis, roll));
  }
  const auto both = markerCornerErrors(lens1280(), poses, {MarkerCornerRefinement::kCornerSubPix, MarkerCornerRefinement::kEdges});
  const MarkerCornerErrors& subpix = both[0];
  const MarkerCornerErrors& edges = both[1];
  const MarkerCornerErrors rim_edges = markerCornerErrors(lens1280(), rim, {MarkerCornerRefinement::kEdges})[0];
  std::printf("cornerSubPix: %d markers, mean outward %+.3f px, RMS %.3f px; edges: %d markers, %+.3f px, RMS %.3f px; "
              "edges at 60–85° off axis: %d markers, %+.3f px, RMS %.3f px\n",
              subpix.markers, subpix.mean_outward_px, subpix.rms_px, edges.markers, edges.mean_outward_px, edges.rms_px,
              rim_edges.markers, rim_edges.mean_outward_px, rim_edges.rms_px);
  ASSERT_EQ(subpix.markers, 24);
  ASSERT_EQ(edges.markers, 24);
  EXPECT_LT(subpix.mean_outward_px, -0.06) << "the bias this refinement exists for (the test can tell)";
  EXPECT_LT(std::abs(edges.mean_outward_px), 0.02);
  EXPECT_LT(edges.rms_px, 0.5 * subpix.rms_px) << "the sides average what one corner window cannot";
  ASSERT_GE(rim_edges.markers, 5);  // OpenCV may miss the one at 85°
  EXPECT_LT(std::abs(rim_edges.mean_outward_px), 0.05);
  EXPECT_LT(rim_edges.rms_px, 0.15);
}

TEST(ArucoDetection, EdgeRefinementRefusesWhatItCannotMeasure) {
  const auto cam = lens1280();
  const Eigen::Isometry3d T = markerPoseFacing(0.6, 0.2, 0.5, 0.2, 1.0, 0.3);
  const GrayImage image = renderTarget(cam.camera, cam.width, cam.height, T, arucoMarkerTexture("DICT_4X4_50", 0, 0.1));
  const auto corners = detectArucoMarker(image, "DICT_4X4_50", 0, DetectionOptions{.marker_corners = MarkerCornerRefinement::kCornerSubPix});
  ASSERT_TRUE(corners);
  EXPECT_TRUE(refineMarkerCornersFromEdges(image, *corners));
  // No contrast: a grey image where the marker was.
  EXPECT_FALSE(refineMarkerCornersFromEdges(GrayImage(cam.width, cam.height, 128), *corners));
  // Too small: a marker of 6 px.
  std::array<Eigen::Vector2d, 4> tiny = {Eigen::Vector2d(100, 100), Eigen::Vector2d(106, 100), Eigen::Vector2d(106, 106),
                                         Eigen::Vector2d(100, 106)};
  EXPECT_FALSE(refineMarkerCornersFromEdges(image, tiny));
  // Cut by the image border: the search across the edges leaves the image.
  std::array<Eigen::Vector2d, 4> at_border = *corners;
  for (auto& c : at_border) c -= (*corners)[0] - Eigen::Vector2d(1.0, 1.0);
  EXPECT_FALSE(refineMarkerCornersFromEdges(image, at_border));
  // Degenerate corners (all on one line) are no marker.
  std::array<Eigen::Vector2d, 4> line = {Eigen::Vector2d(100, 100), Eigen::Vector2d(150, 100), Eigen::Vector2d(200, 100),
                                         Eigen::Vector2d(250, 100)};
  EXPECT_FALSE(refineMarkerCornersFromEdges(image, line));
}

}  // namespace
}  // namespace telesphere::calib
