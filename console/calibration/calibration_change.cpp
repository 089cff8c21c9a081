// SPDX-License-Identifier: MIT
/// @brief withMeasured and differences.
#include "console/calibration/calibration_change.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "calib/camera_resolution.h"

namespace telesphere::console::calibration {

namespace {

void addTransform(std::vector<CalibrationDifference>& out, const std::string& name,
                  const std::optional<Eigen::Isometry3d>& from, const std::optional<Eigen::Isometry3d>& to) {
  if (!from || !to) return;
  const Eigen::Isometry3d delta = from->inverse() * *to;
  out.push_back({name + " translation", delta.translation().norm() * 1000.0, "mm", ""});
  out.push_back({name + " rotation", Eigen::AngleAxisd(delta.linear()).angle() * 180.0 / M_PI, "°", ""});
}

std::string format(const char* pattern, double value) {
  char buf[96];
  std::snprintf(buf, sizeof buf, pattern, value);
  return buf;
}

}  // namespace

calib::SystemCalibration withMeasured(const calib::SystemCalibration& in_use, const calib::SystemCalibration& result,
                                      MeasuredParts parts) {
  calib::SystemCalibration next = in_use;
  switch (parts) {
    case MeasuredParts::kCameras:
      next.cameras = result.cameras;
      next.T_cam_l_cam_r = result.T_cam_l_cam_r;
      break;
    case MeasuredParts::kHandEye:
      if (result.T_flange_cam_l) next.T_flange_cam_l = result.T_flange_cam_l;
      if (result.T_robot_mount) next.T_robot_mount = result.T_robot_mount;
      if (result.T_wrist_marker) next.T_wrist_marker = result.T_wrist_marker;
      break;
  }
  return next;
}

std::vector<CalibrationDifference> differences(const calib::SystemCalibration& from,
                                               const calib::SystemCalibration& to) {
  std::vector<CalibrationDifference> out;
  addTransform(out, "T_flange_cam_l", from.T_flange_cam_l, to.T_flange_cam_l);
  addTransform(out, "T_cam_l_cam_r", from.T_cam_l_cam_r, to.T_cam_l_cam_r);
  for (std::size_t i = 0; i < std::min(from.cameras.size(), to.cameras.size()); ++i) {
    const calib::CameraCalibration& a = from.cameras[i];
    std::string error;
    const auto b = calib::atResolution(to.cameras[i], a.width, a.height, &error);
    CalibrationDifference d{a.label + " image", 0, "px", ""};
    if (!b) {
      d.value = std::nan("");
      d.detail = error;
      out.push_back(d);
      continue;
    }
    constexpr int kGrid = 16;
    std::vector<double> moved;
    for (int gy = 0; gy < kGrid; ++gy) {
      for (int gx = 0; gx < kGrid; ++gx) {
        const Eigen::Vector2d px((gx + 0.5) * a.width / kGrid - 0.5, (gy + 0.5) * a.height / kGrid - 0.5);
        Eigen::Vector3d ray;
        Eigen::Vector2d px_to;
        if (!a.camera.unproject(px, ray) || !b->camera.project(ray, px_to)) continue;
        moved.push_back((px_to - px).norm());
      }
    }
    if (moved.empty()) {
      d.value = std::nan("");
      d.detail = "no pixel both models can map";
    } else {
      std::sort(moved.begin(), moved.end());
      d.value = moved.back();
      d.detail = "max over " + std::to_string(moved.size()) + " grid pixels, median " +
                 format("%.2f px", moved[moved.size() / 2]);
    }
    if (a.camera.modelName() != b->camera.modelName())
      d.detail = std::string(a.camera.modelName()) + " → " + std::string(b->camera.modelName()) + "; " + d.detail;
    out.push_back(d);
  }
  return out;
}

}  // namespace telesphere::console::calibration
