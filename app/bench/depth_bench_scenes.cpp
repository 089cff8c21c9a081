// SPDX-License-Identifier: MIT
/// @brief The depth bench's scenes and their stereo pairs.
#include "app/bench/depth_bench_scenes.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "robot/clock/clock.h"
#include "robot/stereo/stereo_still.h"

namespace telesphere::bench::depth_bench {

using Eigen::Vector3d;
using robot::cameras::SceneHit;
using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;

SyntheticScene makeScene(double near_m) {
  SyntheticScene scene;
  const double front = std::max(3.0, 1.5 * near_m);
  Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
  T_world_room.translation() = Vector3d(0.0, -0.2, (front - 1.0) / 2.0);
  robot::cameras::SurfaceStyle style;
  scene.addRoom("room", T_world_room, Vector3d(2.5, 1.4, (front + 1.0) / 2.0), style, style, style, style);
  if (near_m > 0) {
    const auto at = [](const Vector3d& p) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = p;
      return robot::cameras::fixedPose(T);
    };
    scene.addBox("ahead", at({0.0, 0.0, near_m + 0.1}), Vector3d(0.1, 0.1, 0.1), style);
    const double a = 25.0 * std::numbers::pi / 180.0;
    scene.addBox("left", at({-(near_m + 0.1) * std::sin(a), 0.0, (near_m + 0.1) * std::cos(a)}), Vector3d(0.1, 0.1, 0.1),
                 style);
    const double table_far = near_m + 0.5;
    scene.addBox("table", at({0.0, 0.35 + 0.02, (0.2 + table_far) / 2.0}), Vector3d(0.6, 0.02, (table_far - 0.2) / 2.0),
                 style);
  }
  return scene;
}

std::optional<double> hitDistance(const SyntheticScene& scene, const Vector3d& origin, const Vector3d& d, int* object) {
  Eigen::Isometry3d T_world_origin = Eigen::Isometry3d::Identity();
  T_world_origin.translation() = origin;
  SceneHit hit;
  if (!scene.view(0, T_world_origin).intersect(d, &hit)) return std::nullopt;
  if (object) *object = hit.object;
  return hit.distance;
}

xr::render::InverseDepthGrid trueGrid(const SceneView& camera, double tile_deg) {
  xr::render::InverseDepthGrid grid(tile_deg);
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      std::vector<double> inverse;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          SceneHit hit;
          const Vector3d d = grid.direction(row + (i + 0.5) / 3.0, col + (j + 0.5) / 3.0);
          inverse.push_back(camera.intersect(d, &hit) ? 1.0 / hit.distance : 0.0);
        }
      std::nth_element(inverse.begin(), inverse.begin() + 4, inverse.end());
      grid.at(row, col) = static_cast<float>(inverse[4]);
    }
  return grid;
}

std::vector<std::uint8_t> greyOf(const robot::cameras::CameraFrame& frame) {
  std::string grey, error;
  if (!robot::stereo::toGray8(frame, &grey, &error)) throw std::runtime_error("depth: " + error);
  return {grey.begin(), grey.end()};
}

StereoGrey renderPair(const SyntheticScene& scene, const calib::SystemCalibration& rig, int width, int height, int supersampling,
                      const Eigen::Isometry3d& T_rig_error, const Eigen::Isometry3d& T_world_rig) {
  const auto shared = std::make_shared<const SyntheticScene>(scene);
  robot::clock::SteadyClock clock;
  robot::cameras::SyntheticCameraOptions options;
  options.supersampling = supersampling;
  options.threads = 2;
  StereoGrey pair;
  for (int side = 0; side < 2; ++side) {
    const Eigen::Isometry3d T_world_cam = T_world_rig * (side == 0 ? Eigen::Isometry3d::Identity() : *rig.T_cam_l_cam_r * T_rig_error);
    const robot::cameras::SyntheticCamera camera(rig.cameras[side].camera, width, height, shared,
                                                 robot::cameras::fixedPose(T_world_cam), clock, options);
    (side == 0 ? pair.left : pair.right) = greyOf(camera.renderAt(0));
  }
  return pair;
}

SyntheticScene makeStripesScene() {
  SyntheticScene scene = makeScene(0.0);
  Eigen::Isometry3d T_world_board = Eigen::Isometry3d::Identity();
  T_world_board.linear() = Eigen::AngleAxisd(std::numbers::pi, Vector3d::UnitY()).toRotationMatrix();  // printed side to the camera
  T_world_board.translation() = Vector3d(0.0, 0.0, 0.8);
  constexpr double kPeriodM = 0.02;
  scene.addPlanarTarget(
      "stripes", robot::cameras::fixedPose(T_world_board),
      [](double x, double y) {
        if (std::abs(x) > 0.6 || std::abs(y) > 0.4) return -1;
        const double phase = x / kPeriodM - std::floor(x / kPeriodM);
        return phase < 0.5 ? 40 : 215;
      },
      Eigen::AlignedBox2d(Eigen::Vector2d(-0.6, -0.4), Eigen::Vector2d(0.6, 0.4)));
  return scene;
}

SyntheticScene makeApproachScene(double face_m) {
  SyntheticScene scene = makeScene(0.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Vector3d(0.0, 0.0, face_m + 0.1);
  scene.addBox("approaching", robot::cameras::fixedPose(T), Vector3d(0.1, 0.1, 0.1), robot::cameras::SurfaceStyle{});
  return scene;
}

}  // namespace telesphere::bench::depth_bench
