// SPDX-License-Identifier: MIT
/// @brief The depth tests' room and the board of stripes a stereo pair alone cannot place (#35):
///        shared by the sphere sweep's and the depth worker's tests.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <numbers>

#include "robot/cameras/synthetic_scene.h"

namespace telesphere::xr::test_scenes {

/// A room around a camera at the origin, looking along +z: walls 1–3 m away (object 0).
inline std::shared_ptr<robot::cameras::SyntheticScene> room(bool textured) {
  auto scene = std::make_shared<robot::cameras::SyntheticScene>();
  robot::cameras::SurfaceStyle style;
  style.pattern = textured;
  Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
  T_world_room.translation() = Eigen::Vector3d(0.0, -0.2, 1.0);
  scene->addRoom("room", T_world_room, Eigen::Vector3d(2.5, 1.4, 2.0), style, style, style, style);
  return scene;
}

/// A 1.2 × 0.8 m board of vertical stripes 2 cm apart, printed side toward −z, centred at
/// `p_world_centre` (at 0.8 m the period is 1.4°, a third of a 64 mm pair's disparity: it matches
/// at several depths along the baseline).
inline void addStripesBoard(robot::cameras::SyntheticScene& scene, const Eigen::Vector3d& p_world_centre) {
  Eigen::Isometry3d T_world_board(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY()));
  T_world_board.translation() = p_world_centre;
  scene.addPlanarTarget(
      "stripes", robot::cameras::fixedPose(T_world_board),
      [](double x, double y) {
        if (std::abs(x) > 0.6 || std::abs(y) > 0.4) return -1;
        return x / 0.02 - std::floor(x / 0.02) < 0.5 ? 40 : 215;
      },
      Eigen::AlignedBox2d(Eigen::Vector2d(-0.6, -0.4), Eigen::Vector2d(0.6, 0.4)));
}

}  // namespace telesphere::xr::test_scenes
