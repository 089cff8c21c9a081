// SPDX-License-Identifier: MIT
/// @brief Where to put the head so that a fixed Aprilgrid lands where the intrinsic calibration
///        still needs it (issue #15, paper §III-B): the board's centre at chosen pixels all over
///        the image, out to its corners (the widest polar angles of a lens beyond 180° lie
///        there), with the board rolled in the image and seen from a few head positions.
///
/// For a target pixel p the camera must see the board centre along d_des = unproject(p) (camera
/// frame). From the start pose (head T_robot_head0, camera R_robot_cam0 = R_robot_head0·R_head_cam)
/// the camera turns by the smallest rotation that takes R_robot_cam0·d_des onto the board's
/// direction d_robot from the camera's new position, then rolls by ρ about d_robot:
///   R_robot_cam = Rot(d_robot, ρ) · Rmin(R_robot_cam0·d_des → d_robot) · R_robot_cam0,
/// which leaves R_robot_cam·d_des = d_robot. The camera's position depends on the head's
/// rotation (the camera is off the head's centre), so d_robot is recomputed and the rotation
/// solved again until it no longer changes (a fixed point; the residual is tested below 1e-6 px).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "calib/aprilgrid.h"
#include "calib/generic_camera.h"
#include "calib/target_detection.h"

namespace telesphere::console::calibration {

struct PlannedView {
  Eigen::Isometry3d T_robot_head = Eigen::Isometry3d::Identity();
  Eigen::Vector2d target_px = Eigen::Vector2d::Zero();  ///< where the board centre should appear
  double roll_deg = 0;
  int target = 0;         ///< index into ViewPlanOptions::targets
  /// Another head pose for the same target (another roll, another head position): visited only
  /// when the arm refused every pose before it for this target.
  bool fallback = false;
};

struct ViewPlanOptions {
  /// Board-centre targets as fractions of the image (0…1 in x and y), in the order visited.
  std::vector<Eigen::Vector2d> targets;
  /// Rolls about the board's direction, used in turn (deg).
  std::vector<double> rolls_deg{0.0, 30.0, -30.0};
  /// Head position offsets from the start, used in turn (robot frame, m; keep them inside the
  /// head workspace).
  /// Poses that turn the head further than this from the start are left out (no head arm turns
  /// round; near 180° the smallest rotation is ill-defined).
  double max_turn_deg = 150.0;
  std::vector<Eigen::Vector3d> offsets_m{Eigen::Vector3d::Zero(), Eigen::Vector3d(0.08, 0.05, 0.03),
                                         Eigen::Vector3d(-0.08, -0.05, -0.03)};
  /// Per target, up to this many further poses (the next roll, then the next head offset, in
  /// turn) for when the arm cannot reach the first: which poses the arm refuses depends on where
  /// it stands, and a rim target lost that way can leave a polar bin without a corner.
  int fallbacks = 4;

  /// The image's inner part: a 3×3 grid at 25/50/75 % (a first solve needs these).
  static std::vector<Eigen::Vector2d> innerTargets();
  /// Out to the rim: the edges' middles at 4 % from the border, the corners at 7 % (closer in,
  /// the board is cut by the border and too squeezed to detect), the ring between (15/85 %) and
  /// points near the edges.
  static std::vector<Eigen::Vector2d> outerTargets();
  /// Between the two (35/65 %, the centre, and the edges' middles at 10 %): views to top up with.
  static std::vector<Eigen::Vector2d> fillTargets();
};

/// The board centre in the camera frame from one view (its corners' bearings through `camera`
/// and the board's geometry); nothing if the view does not give a pose.
std::optional<Eigen::Vector3d> boardCentreInCamera(const calib::TargetObservation& view, const calib::AprilGrid& grid,
                                                   const calib::GenericCamera& camera);

/// The head poses that put a board centre at `p_robot_board` onto each target pixel of a camera
/// `camera` (width × height) mounted at T_head_cam, starting from T_robot_head0. Targets the
/// model cannot unproject, that need a turn beyond max_turn_deg, or whose pose does not show the
/// board within 0.01 px of the target are left out. Each target's first pose is followed by its
/// fallbacks (PlannedView::fallback), which show the board centre on the same pixel.
std::vector<PlannedView> planIntrinsicViews(const Eigen::Isometry3d& T_robot_head0, const Eigen::Isometry3d& T_head_cam,
                                            const Eigen::Vector3d& p_robot_board, const calib::GenericCamera& camera,
                                            int width, int height, const ViewPlanOptions& options);

}  // namespace telesphere::console::calibration
