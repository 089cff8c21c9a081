// SPDX-License-Identifier: MIT
/// @brief planIntrinsicViews (see intrinsics_view_plan.h).
#include "console/calibration/intrinsics_view_plan.h"

#include <algorithm>
#include <cmath>

#include "calib/bearing_pose.h"

namespace telesphere::console::calibration {

std::vector<Eigen::Vector2d> ViewPlanOptions::innerTargets() {
  std::vector<Eigen::Vector2d> t;
  for (double y : {0.5, 0.25, 0.75})
    for (double x : {0.5, 0.25, 0.75}) t.emplace_back(x, y);
  return t;
}

std::vector<Eigen::Vector2d> ViewPlanOptions::outerTargets() {
  return {{0.04, 0.5},  {0.96, 0.5},  {0.5, 0.04},  {0.5, 0.96},  {0.07, 0.07}, {0.93, 0.07}, {0.07, 0.93},
          {0.93, 0.93}, {0.15, 0.15}, {0.85, 0.15}, {0.15, 0.85}, {0.85, 0.85}, {0.15, 0.5},  {0.85, 0.5},
          {0.5, 0.15},  {0.5, 0.85},  {0.02, 0.25}, {0.98, 0.75}, {0.25, 0.02}, {0.75, 0.98}};
}

std::vector<Eigen::Vector2d> ViewPlanOptions::fillTargets() {
  return {{0.5, 0.5},   {0.35, 0.35}, {0.65, 0.35}, {0.35, 0.65}, {0.65, 0.65},
          {0.1, 0.5},   {0.9, 0.5},   {0.5, 0.1},   {0.5, 0.9}};
}

std::optional<Eigen::Vector3d> boardCentreInCamera(const calib::TargetObservation& view, const calib::AprilGrid& grid,
                                                   const calib::GenericCamera& camera) {
  std::vector<Eigen::Vector3d> p_board, d_cam;
  for (std::size_t i = 0; i < view.corner_ids.size(); ++i) {
    Eigen::Vector3d d;
    if (!camera.unproject(view.corners_px[i], d) || !d.allFinite() || d.norm() == 0) continue;
    p_board.push_back(grid.cornerPosition(view.corner_ids[i]));
    d_cam.push_back(d.normalized());
  }
  if (p_board.size() < 4) return std::nullopt;
  const auto T_cam_board = calib::planarPoseFromBearings(p_board, d_cam);
  if (!T_cam_board) return std::nullopt;
  return *T_cam_board * Eigen::Vector3d(grid.width() / 2, grid.height() / 2, 0.0);
}

std::vector<PlannedView> planIntrinsicViews(const Eigen::Isometry3d& T_robot_head0, const Eigen::Isometry3d& T_head_cam,
                                            const Eigen::Vector3d& p_robot_board, const calib::GenericCamera& camera,
                                            int width, int height, const ViewPlanOptions& options) {
  std::vector<PlannedView> plan;
  const Eigen::Matrix3d R_robot_cam0 = T_robot_head0.linear() * T_head_cam.linear();
  const Eigen::Matrix3d R_cam_head = T_head_cam.linear().transpose();
  const std::size_t rolls = std::max<std::size_t>(1, options.rolls_deg.size());
  const std::size_t offsets = std::max<std::size_t>(1, options.offsets_m.size());
  for (std::size_t i = 0; i < options.targets.size(); ++i) {
    const Eigen::Vector2d px(options.targets[i].x() * (width - 1), options.targets[i].y() * (height - 1));
    Eigen::Vector3d d_des;
    if (!camera.unproject(px, d_des) || !d_des.allFinite() || d_des.norm() == 0) continue;
    d_des.normalize();
    // Candidate k takes the roll i + k and the offset i + k / rolls in turn: k = 0 is the pose
    // this target always had; the fallbacks first roll, then move the head.
    int poses = 0;
    for (std::size_t k = 0; k < rolls * offsets && poses <= std::max(0, options.fallbacks); ++k) {
      const double roll = options.rolls_deg.empty() ? 0.0 : options.rolls_deg[(i + k) % rolls];
      const Eigen::Vector3d offset =
          options.offsets_m.empty() ? Eigen::Vector3d::Zero() : options.offsets_m[(i + k / rolls) % offsets];
      const Eigen::Vector3d p_head = T_robot_head0.translation() + offset;
      Eigen::Matrix3d R_robot_cam = R_robot_cam0;
      Eigen::Vector3d d_last = Eigen::Vector3d::Zero();
      for (int pass = 0; pass < 50; ++pass) {  // a contraction by about |t_head_cam| / distance per pass
        const Eigen::Vector3d p_cam = p_head + R_robot_cam * R_cam_head * T_head_cam.translation();
        const Eigen::Vector3d d_robot = (p_robot_board - p_cam).normalized();
        if ((d_robot - d_last).norm() < 1e-14) break;
        d_last = d_robot;
        const Eigen::Matrix3d R_min =
            Eigen::Quaterniond::FromTwoVectors(R_robot_cam0 * d_des, d_robot).toRotationMatrix();
        R_robot_cam = Eigen::AngleAxisd(roll * M_PI / 180.0, d_robot).toRotationMatrix() * R_min * R_robot_cam0;
      }
      PlannedView view;
      view.T_robot_head.linear() = R_robot_cam * R_cam_head;
      view.T_robot_head.translation() = p_head;
      const double turn_deg =
          Eigen::AngleAxisd(T_robot_head0.linear().transpose() * view.T_robot_head.linear()).angle() * 180.0 / M_PI;
      if (turn_deg > options.max_turn_deg) continue;
      const Eigen::Isometry3d T_robot_cam = view.T_robot_head * T_head_cam;
      Eigen::Vector2d shown;
      if (!camera.project(T_robot_cam.inverse() * p_robot_board, shown) || (shown - px).norm() > 0.01) continue;
      view.target_px = px;
      view.roll_deg = roll;
      view.target = int(i);
      view.fallback = poses > 0;
      plan.push_back(view);
      ++poses;
    }
  }
  return plan;
}

}  // namespace telesphere::console::calibration
