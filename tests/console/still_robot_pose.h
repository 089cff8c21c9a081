// SPDX-License-Identifier: MIT
/// @brief For the headless calibration tests: where the robot's head or flange stands once it is
///        still (a run must leave the arm where it found it), read from its RobotState on the link.
#pragma once

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>
#include <utility>

#include "robot/link/link_client.h"
#include "robot/link/link_pose.h"

namespace telesphere::test {

enum class RobotFrame { kHead, kFlange };

/// The pose of `frame` in the robot frame once two states 0.5 s apart agree within 0.1 mm;
/// nothing if that does not happen within 20 s.
inline std::optional<Eigen::Isometry3d> stillRobotPose(link::LinkClient& probe, RobotFrame frame) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::optional<Eigen::Isometry3d> last;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto state = probe.latestRobotState();
    const bool has = state && (frame == RobotFrame::kHead ? state->has_t_robot_head() : state->has_t_robot_flange());
    if (has) {
      const Eigen::Isometry3d T =
          link::fromLinkPose(frame == RobotFrame::kHead ? state->t_robot_head() : state->t_robot_flange());
      if (last && (last->translation() - T.translation()).norm() < 1e-4) return T;
      last = T;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return std::nullopt;
}

/// The pose of `frame` in the robot's newest state, as soon as there is one (within 20 s). For a
/// run's start, where nothing has moved the arm yet: waiting for stillness would start the run
/// later against the simulated manipulator's timed motion, and so on other samples.
inline std::optional<Eigen::Isometry3d> currentRobotPose(link::LinkClient& probe, RobotFrame frame) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    const auto state = probe.latestRobotState();
    if (state && (frame == RobotFrame::kHead ? state->has_t_robot_head() : state->has_t_robot_flange()))
      return link::fromLinkPose(frame == RobotFrame::kHead ? state->t_robot_head() : state->t_robot_flange());
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return std::nullopt;
}

/// How far `after` is from `before`: {mm, degrees}.
inline std::pair<double, double> distanceMmDeg(const Eigen::Isometry3d& before, const Eigen::Isometry3d& after) {
  return {(after.translation() - before.translation()).norm() * 1000.0,
          Eigen::AngleAxisd(before.linear().transpose() * after.linear()).angle() * 180.0 / M_PI};
}

}  // namespace telesphere::test
