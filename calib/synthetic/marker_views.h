// SPDX-License-Identifier: MIT
/// @brief The hand-eye marker rendered at known poses and detected, against the true corners:
///        shared by the detection tests and `telesphere-bench calib` (table "marker corners").
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "calib/synthetic/calibration_sessions.h"
#include "calib/hand_eye_calibration.h"
#include "calib/target_detection.h"
#include "calib/target_render.h"

namespace telesphere::calib::synthetic {

/// A marker whose centre lies `theta` off the optical axis (azimuth `phi`) at `distance`, its
/// face turned to the camera, then tilted by `tilt` about an axis across the line of sight (at
/// angle `axis`) and rolled by `roll` about its own normal.
inline Eigen::Isometry3d markerPoseFacing(double distance, double theta, double phi, double tilt, double axis, double roll) {
  const Eigen::Vector3d direction(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  const Eigen::Matrix3d R_facing = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), direction).toRotationMatrix();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_facing * Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)).toRotationMatrix() *
               Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix() *
               Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = distance * direction;
  return T;
}

/// `n` markers as the head sees the wrist marker: 0.45–0.8 m away, their centres `from_deg` to
/// `to_deg` off axis in any direction, tilted up to 34° about a random axis, any roll.
inline std::vector<Eigen::Isometry3d> randomMarkerPosesFacing(int n, double from_deg, double to_deg, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < n; ++i) {
    const double distance = 0.45 + 0.35 * u(rng);
    const double theta = (from_deg + (to_deg - from_deg) * u(rng)) * M_PI / 180;
    poses.push_back(markerPoseFacing(distance, theta, 2 * M_PI * u(rng), 0.6 * u(rng), 2 * M_PI * u(rng), 2 * M_PI * u(rng)));
  }
  return poses;
}

/// Detected marker corners against the true projections: the mean of the error along the
/// direction from the marker's centre out through the corner (negative: the marker looks
/// smaller, hence farther), the RMS, and the detection's time.
struct MarkerCornerErrors {
  int markers = 0, corners = 0;
  double mean_outward_px = 0, rms_px = 0;
  double detect_ms_per_image = 0;  ///< OpenCV's detection and the refinement
};

/// The 10 cm DICT_4X4_50 marker (id 0) rendered once per pose through `cam` (3×3 supersampled,
/// 2 grey levels of noise, seeded by the pose's index) and detected with every refinement.
inline std::vector<MarkerCornerErrors> markerCornerErrors(const SyntheticCamera& cam,
                                                          const std::vector<Eigen::Isometry3d>& poses,
                                                          const std::vector<MarkerCornerRefinement>& refinements) {
  constexpr double kSize = 0.1;
  std::vector<MarkerCornerErrors> out(refinements.size());
  std::vector<double> sum_outward(refinements.size(), 0.0), sum2(refinements.size(), 0.0), seconds(refinements.size(), 0.0);
  const auto corners_in_marker = markerCorners(kSize);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    RenderOptions render;
    render.noise_sigma = 2.0;
    render.noise_seed = static_cast<std::uint32_t>(i + 1);
    const GrayImage image =
        renderTarget(cam.camera, cam.width, cam.height, poses[i], arucoMarkerTexture("DICT_4X4_50", 0, kSize), render);
    Eigen::Vector2d centre;
    if (!cam.camera.project(poses[i].translation(), centre)) continue;
    for (std::size_t r = 0; r < refinements.size(); ++r) {
      DetectionOptions options;
      options.marker_corners = refinements[r];
      const auto t0 = std::chrono::steady_clock::now();
      const auto corners = detectArucoMarker(image, "DICT_4X4_50", 0, options);
      seconds[r] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!corners) continue;
      ++out[r].markers;
      for (std::size_t k = 0; k < 4; ++k) {
        Eigen::Vector2d truth;
        if (!cam.camera.project(poses[i] * corners_in_marker[k], truth)) continue;
        const Eigen::Vector2d e = (*corners)[k] - truth;
        sum_outward[r] += e.dot((truth - centre).normalized());
        sum2[r] += e.squaredNorm();
        ++out[r].corners;
      }
    }
  }
  for (std::size_t r = 0; r < refinements.size(); ++r) {
    out[r].mean_outward_px = sum_outward[r] / std::max(out[r].corners, 1);
    out[r].rms_px = std::sqrt(sum2[r] / std::max(out[r].corners, 1));
    out[r].detect_ms_per_image = 1e3 * seconds[r] / std::max<std::size_t>(poses.size(), 1);
  }
  return out;
}

}  // namespace telesphere::calib::synthetic
