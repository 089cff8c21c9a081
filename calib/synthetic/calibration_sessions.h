// SPDX-License-Identifier: MIT
/// @brief Synthetic calibration data with known ground truth, shared by the calibration tests and
///        `telesphere-bench calib`: the paper's >180° double-sphere lens at 4K and at 1280×1024,
///        Aprilgrid poses spread over the whole image (the rim and beyond 90° off-axis included),
///        corner observations projected through the true model with seeded Gaussian pixel noise,
///        and simulated hand-eye sessions (head and wrist poses, marker corners in both cameras).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "calib/aprilgrid.h"
#include "calib/generic_camera.h"
#include "calib/hand_eye_calibration.h"
#include "calib/intrinsic_calibration.h"
#include "calib/synthetic/typical_lenses.h"

namespace telesphere::calib::synthetic {

struct SyntheticCamera {
  calib::GenericCamera camera;
  int width = 0, height = 0;
};

/// The paper's lens on a 3840×2160 sensor: ds [930, 931, 1919.5, 1079.5, −0.18, 0.59], about
/// 196° across the image width.
inline SyntheticCamera lens4k() {
  const Eigen::VectorXd p = TypicalLens<calib::DoubleSphereCamera>::parameters();
  return {*calib::GenericCamera::create("ds", p), kTypicalSensorWidthPx, kTypicalSensorHeightPx};
}

/// The same kind of lens on a 1280×1024 sensor (≈195° across the width); `right` gives the
/// slightly different right camera of a stereo pair.
inline SyntheticCamera lens1280(bool right = false) {
  Eigen::VectorXd p(6);
  if (right)
    p << 318, 317.5, 643.2, 508.9, -0.16, 0.6;
  else
    p << 315, 315.6, 639.5, 511.5, -0.18, 0.59;
  return {*calib::GenericCamera::create("ds", p), 1280, 1024};
}

/// Right camera of the stereo pair in the left camera's frame: 6.4 cm baseline, slight rotation.
inline Eigen::Isometry3d trueTCamLCamR() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(-0.01, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() << 0.064, 0.001, -0.002;
  return T;
}

inline calib::AprilGrid testGrid() { return calib::AprilGrid{6, 6, 0.088, 0.3}; }

/// A board pose whose centre lies at angle `theta` off the optical axis (azimuth `phi`) at
/// `distance` metres, its face turned towards the camera and tilted by up to `tilt` rad.
inline Eigen::Isometry3d boardPoseAt(const calib::AprilGrid& grid, double theta, double phi,
                                     double distance, double tilt_x, double tilt_y, double roll) {
  const Eigen::Vector3d dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                            std::cos(theta));
  // Board z towards the camera, board x roughly along camera x (board y up = camera −y).
  const Eigen::Vector3d z_b = -dir;
  Eigen::Vector3d x_b = Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(z_b) * z_b;
  if (x_b.norm() < 1e-3) x_b = Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY().dot(z_b) * z_b;
  x_b.normalize();
  Eigen::Matrix3d R;
  R.col(0) = x_b;
  R.col(2) = z_b;
  R.col(1) = z_b.cross(x_b);
  R = R * (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
           Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()))
              .toRotationMatrix();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  const Eigen::Vector3d centre(grid.width() / 2, grid.height() / 2, 0);
  T.translation() = distance * dir - R * centre;
  return T;
}

/// Corners of `grid` at T_cam_board that project inside the image (4 px margin), with noise.
inline calib::TargetObservation observeBoard(const SyntheticCamera& cam, const calib::AprilGrid& grid,
                                             const Eigen::Isometry3d& T_cam_board,
                                             double noise_px, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, noise_px);
  calib::TargetObservation obs;
  for (int id = 0; id < grid.numCorners(); ++id) {
    const Eigen::Vector3d p_cam = T_cam_board * grid.cornerPosition(id);
    Eigen::Vector2d px;
    if (!cam.camera.project(p_cam, px)) continue;
    // The board must face the camera at this corner (a printed board is opaque).
    if (p_cam.dot(T_cam_board.linear().col(2)) > 0) continue;
    if (px.x() < 4 || px.y() < 4 || px.x() > cam.width - 5 || px.y() > cam.height - 5) continue;
    obs.corner_ids.push_back(id);
    obs.corners_px.push_back(px + Eigen::Vector2d(noise(rng), noise(rng)));
  }
  obs.tags_detected = static_cast<int>(obs.corner_ids.size() / 4);
  return obs;
}

/// `n` board poses spread over the image of `cam` (ring by ring from the centre out to
/// `max_theta`, beyond 90° for the fisheye, so the image rim is covered), each tilted by up to
/// `max_tilt` rad about a random axis in the board plane (strong tilts: the foreshortening
/// separates focal length from distance and distortion) and seen with at least 16 corners.
inline std::vector<Eigen::Isometry3d> spreadBoardPoses(const SyntheticCamera& cam,
                                                      const calib::AprilGrid& grid, int n,
                                                      double max_theta, std::mt19937& rng,
                                                      double max_tilt = 1.0) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Eigen::Isometry3d> poses;
  std::mt19937 probe_rng(0);
  for (int tries = 0; static_cast<int>(poses.size()) < n && tries < 100 * n; ++tries) {
    const int i = static_cast<int>(poses.size());
    const double theta = max_theta * std::sqrt((i + u01(rng)) / n);
    const double phi = 2 * M_PI * u01(rng);
    const double distance = 0.45 + 0.6 * u01(rng);
    const double tilt = max_tilt * u01(rng), tilt_axis = 2 * M_PI * u01(rng);
    const Eigen::Isometry3d T = boardPoseAt(grid, theta, phi, distance, tilt * std::cos(tilt_axis),
                                            tilt * std::sin(tilt_axis), 0.6 * (u01(rng) - 0.5));
    if (observeBoard(cam, grid, T, 0.0, probe_rng).corner_ids.size() < 16) continue;
    poses.push_back(T);
  }
  return poses;
}

/// A deliberately degenerate set: `n` views with the board fronto-parallel at the image centre
/// (no tilt, distance 0.45–1.05 m, any roll): focal length and distortion trade off.
inline std::vector<Eigen::Isometry3d> frontoParallelCentreBoardPoses(const calib::AprilGrid& grid, int n,
                                                                    std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < n; ++i)
    poses.push_back(boardPoseAt(grid, 0.0, 0.0, 0.45 + 0.6 * u01(rng), 0.0, 0.0, M_PI * (u01(rng) - 0.5)));
  return poses;
}

/// The true hand-eye transforms of the simulated sessions.
struct HandEyeTruth {
  Eigen::Isometry3d T_flange_cam_l, T_robot_mount, T_wrist_marker;
};

inline Eigen::Isometry3d poseOf(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (rotation_vector.norm() > 0)
    T.linear() = Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

inline HandEyeTruth handEyeTruth() {
  return {poseOf({0.05, -0.1, 1.52}, {0.03, -0.06, 0.11}),   // camera on the head flange
          poseOf({0.0, 0.0, 0.3}, {0.55, 0.25, -0.4}),       // manipulator base in the head-arm base
          poseOf({0.2, -0.1, 0.05}, {0.0, 0.02, 0.09})};     // marker on the wrist
}

/// A simulated session: the head moves in a sinusoid about two axes (yaw and pitch, or yaw only
/// when `head_two_axes` is false) while the marker is held at random poses in front of the
/// cameras; wrist poses follow from the truth. Marker corners observed in both cameras with
/// Gaussian noise; samples where a corner leaves an image are dropped. `head_pose_at`, when
/// given, replaces the sinusoid: T_robot_flange of attempt i (e.g. forward kinematics of joint
/// angles chosen by the caller).
inline std::vector<calib::HandEyeSample> simulateHandEyeSession(
    const HandEyeTruth& truth, const SyntheticCamera& cam_l, const SyntheticCamera& cam_r,
    const Eigen::Isometry3d& T_cam_l_cam_r, double marker_size, int n, double noise_px,
    std::uint32_t seed, bool head_two_axes = true,
    const std::function<Eigen::Isometry3d(int)>& head_pose_at = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const auto corners = calib::markerCorners(marker_size);
  std::vector<calib::HandEyeSample> samples;
  for (int i = 0; static_cast<int>(samples.size()) < n && i < 20 * n; ++i) {
    const double phase = 0.37 * i;
    const Eigen::Isometry3d F = head_pose_at ? head_pose_at(i) : poseOf(
        Eigen::Vector3d(0, head_two_axes ? 0.35 * std::sin(1.3 * phase) : 0.0, 0.6 * std::sin(phase)),
        Eigen::Vector3d(0.3 + 0.05 * std::sin(phase), 0.05 * std::cos(phase), 1.2 + 0.03 * std::sin(2 * phase)));
    // Marker in front of cam_l, 0.35–0.7 m away, up to ~45° off-axis, facing the camera ±35°.
    const Eigen::Vector3d dir = Eigen::Vector3d(0.8 * u(rng), 0.8 * u(rng), 1.0).normalized();
    const double dist = 0.525 + 0.175 * u(rng);
    const Eigen::Isometry3d M =
        poseOf(Eigen::Vector3d(M_PI + 0.6 * u(rng), 0.6 * u(rng), 1.5 * u(rng)), dist * dir);
    calib::HandEyeSample s;
    s.t_ns = static_cast<std::int64_t>(i) * 100000000;
    s.T_robot_flange = F;
    s.T_mount_wrist = truth.T_robot_mount.inverse() * F * truth.T_flange_cam_l * M *
                      truth.T_wrist_marker.inverse();
    bool ok = true;
    for (int c = 0; c < 2 && ok; ++c) {
      const SyntheticCamera& cam = c == 0 ? cam_l : cam_r;
      const Eigen::Isometry3d T_cam_marker = c == 0 ? M : T_cam_l_cam_r.inverse() * M;
      std::array<Eigen::Vector2d, 4> px;
      for (std::size_t k = 0; k < 4 && ok; ++k) {
        ok = cam.camera.project(T_cam_marker * corners[k], px[k]) && px[k].x() > 4 &&
             px[k].y() > 4 && px[k].x() < cam.width - 5 && px[k].y() < cam.height - 5;
        px[k] += Eigen::Vector2d(noise(rng), noise(rng));
      }
      (c == 0 ? s.corners_l : s.corners_r) = px;
    }
    if (ok) samples.push_back(s);
  }
  return samples;
}

/// 100 000 unit directions in front of and beside the camera (θ < 100°), for timing projection.
inline std::vector<Eigen::Vector3d> sphereDirectionsForBench() {
  std::vector<Eigen::Vector3d> out;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  while (out.size() < 100000) {
    const Eigen::Vector3d d(u(rng), u(rng), u(rng));
    if (d.squaredNorm() > 1.0 || d.squaredNorm() < 1e-6 || d.normalized().z() < -0.17) continue;
    out.push_back(d.normalized());
  }
  return out;
}

/// Rotation angle between two poses (deg) and distance between their origins (m).
inline double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}
inline double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

}  // namespace telesphere::calib::synthetic
