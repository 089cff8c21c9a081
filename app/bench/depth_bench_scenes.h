// SPDX-License-Identifier: MIT
/// @brief The depth bench's synthetic scenes (`telesphere-bench depth`, #35): rooms with near
///        objects, a board of stripes, an approaching cube; their true depth along a ray and per
///        grid tile; and their stereo pair rendered through the simulated rig.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "calib/system_calibration.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::bench::depth_bench {

/// The camera at the origin of a room's frame, looking along +z (x right, y down): floor 1.2 m
/// below, ceiling 1.6 m above, side walls 2.5 m away, a wall 1 m behind and one ahead at
/// max(3 m, 1.5 × the near objects' depth). With `near_m` > 0: a 20 cm cube straight ahead and one
/// 25° to the left with their faces at near_m, and a table top 35 cm below the camera from 0.2 m
/// to beyond them (the grasping workspace).
robot::cameras::SyntheticScene makeScene(double near_m);

/// The room and, 0.8 m ahead, a 1.2 × 0.8 m board of vertical stripes 2 cm apart (1.4° at
/// 0.8 m, a third of the pair's disparity there): a pattern that matches at many depths.
robot::cameras::SyntheticScene makeStripesScene();

/// The room and one 20 cm cube straight ahead with its face at `face_m` (an approaching object).
robot::cameras::SyntheticScene makeApproachScene(double face_m);

/// Distance along unit `d` from `origin` (room frame, the camera's orientation) to the scene.
/// With `object`: the index of the object hit (0: the room).
std::optional<double> hitDistance(const robot::cameras::SyntheticScene& scene, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& d, int* object = nullptr);

/// The oracle grid: each tile's median inverse depth over 3 × 3 rays inside it.
xr::render::InverseDepthGrid trueGrid(const robot::cameras::SceneView& camera, double tile_deg);

/// The grey of a rendered frame (robot::stereo::toGray8), rows `width` bytes apart.
std::vector<std::uint8_t> greyOf(const robot::cameras::CameraFrame& frame);

/// The stereo pair of a scene through the simulated rig (the left camera at the scene's origin).
struct StereoGrey {
  std::vector<std::uint8_t> left, right;
};
/// `T_rig_error` turns the right camera away from where `rig` says it is (a calibration error the
/// sweep does not know about); `T_world_rig` puts the rig (its left camera) elsewhere than the origin.
StereoGrey renderPair(const robot::cameras::SyntheticScene& scene, const calib::SystemCalibration& rig, int width, int height,
                      int supersampling, const Eigen::Isometry3d& T_rig_error = Eigen::Isometry3d::Identity(),
                      const Eigen::Isometry3d& T_world_rig = Eigen::Isometry3d::Identity());

}  // namespace telesphere::bench::depth_bench
