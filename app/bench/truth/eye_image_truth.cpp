// SPDX-License-Identifier: MIT
/// @brief The geometric check of the operator's eye images (see eye_image_truth.h).
#include "app/bench/truth/eye_image_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "calib/camera_resolution.h"
#include "xr/render/sphere_geometry.h"

namespace telesphere::truth {

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(position));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (position - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

std::optional<FrameEyeError> evaluateEyeImages(const XrTruthFrame& frame, const std::vector<float>& map,
                                               const RobotTruthRow& robot, const calib::SystemCalibration& calibration,
                                               const robot::cameras::SyntheticScene& scene, const EyeErrorOptions& options,
                                               std::string* error) {
  if (!robot.mapping_set) {
    *error = "frame " + std::to_string(frame.stereo_sequence) + ": no nominal mapping on the robot yet";
    return std::nullopt;
  }
  if (calibration.cameras.size() != 2) {
    *error = "the true calibration needs two cameras";
    return std::nullopt;
  }
  const std::size_t pixels = static_cast<std::size_t>(frame.width) * frame.height;
  if (map.size() != pixels * 4) {
    *error = "projection map of the wrong size";
    return std::nullopt;
  }
  FrameEyeError out;
  const int stride = std::max(1, options.stride);
  for (int eye = 0; eye < 2; ++eye) {
    if (!robot.T_robot_cam_true[eye]) {
      *error = "frame " + std::to_string(frame.stereo_sequence) + ": the truth does not cover its capture time";
      return std::nullopt;
    }
    const auto camera = calib::atResolution(calibration.cameras[eye], frame.image_width, frame.image_height, error);
    if (!camera) return std::nullopt;
    const Eigen::Isometry3d& T_robot_cam = *robot.T_robot_cam_true[eye];
    Eigen::Isometry3d T_hmd_eye = Eigen::Isometry3d::Identity();
    T_hmd_eye.translation().x() = (eye == 0 ? -0.5 : 0.5) * frame.ipd_m;
    const Eigen::Isometry3d T_robot_eye = robot.T_robot_vr * frame.T_vr_hmd * T_hmd_eye;
    if (eye == 0) {
      out.eye_camera_distance_m = (T_robot_eye.translation() - T_robot_cam.translation()).norm();
      const Eigen::Isometry3d d = T_robot_cam.inverse() * frame.T_robot_cam_stamped[0];
      out.stamp_position_error_m = d.translation().norm();
      out.stamp_angle_error_deg = Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI;
    }
    const robot::cameras::SceneView view = scene.view(robot.capture_ns[eye], T_robot_cam);
    const float* eye_map = &map[static_cast<std::size_t>(eye) * pixels * 2];
    for (int row = stride / 2; row < frame.height; row += stride) {
      for (int col = stride / 2; col < frame.width; col += stride) {
        ++out.evaluated;
        const float* px = &eye_map[(static_cast<std::size_t>(row) * frame.width + col) * 2];
        if (!std::isfinite(px[0]) || !std::isfinite(px[1])) {
          ++out.blind;
          continue;
        }
        Eigen::Vector3d d_cam;
        if (!camera->camera.unproject(Eigen::Vector2d(px[0], px[1]), d_cam)) {
          ++out.blind;
          continue;
        }
        d_cam.normalize();
        robot::cameras::SceneHit hit;
        if (!view.intersect(d_cam, &hit)) {
          ++out.no_scene;
          continue;
        }
        const Eigen::Vector3d p_robot_scene = T_robot_cam * (hit.distance * d_cam);
        const Eigen::Vector3d d_eye =
            T_robot_eye.linear() * xr::render::eyeRay(frame.fov, frame.width, frame.height, col, row).normalized();
        const Eigen::Vector3d to_scene = (p_robot_scene - T_robot_eye.translation()).normalized();
        out.error_deg.push_back(std::atan2(d_eye.cross(to_scene).norm(), d_eye.dot(to_scene)) * 180.0 / M_PI);
      }
    }
  }
  return out;
}

}  // namespace telesphere::truth
