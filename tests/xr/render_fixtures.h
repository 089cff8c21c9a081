// SPDX-License-Identifier: MIT
/// @brief What the renderer tests share: the typical lens of each camera model (from
///        tests/calib/camera_model_fixtures.h) scaled to a 960×540 image so that the suite stays
///        fast, eye poses covering the extremes, and small pose helpers.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "calib/generic_camera.h"
#include "tests/calib/camera_model_fixtures.h"
#include "xr/render/eye_view.h"

namespace telesphere::test {

inline constexpr int kScale = 4;
inline constexpr int kImageWidth = kWidth / kScale;    // 960
inline constexpr int kImageHeight = kHeight / kScale;  // 540

/// A lens of model `Model` for a sensor scaled by 1/kScale: focal lengths and principal point
/// scaled (pixel centres stay pixel centres), distortion unchanged.
template <template <typename> class Model>
calib::GenericCamera scaledTypicalLens() {
  auto p = Lens<Model>::typical();
  p[0] /= kScale;
  p[1] /= kScale;
  p[2] = (p[2] + 0.5) / kScale - 0.5;
  p[3] = (p[3] + 0.5) / kScale - 0.5;
  return calib::GenericCamera(Model<double>(p));
}

struct NamedCamera {
  std::string name;
  calib::GenericCamera camera;
};

inline std::vector<NamedCamera> allTypicalLenses() {
  return {{"ds", scaledTypicalLens<calib::DoubleSphereCamera>()},
          {"eucm", scaledTypicalLens<calib::ExtendedUnifiedCamera>()},
          {"kb4", scaledTypicalLens<calib::KannalaBrandtCamera>()},
          {"pinhole", scaledTypicalLens<calib::PinholeRadtanCamera>()}};
}

/// T_cam_eye of an eye at t_cam (camera frame, m) looking along the camera's axis, then rotated
/// by `R_turn` (in the camera frame).
inline Eigen::Isometry3d eyePose(const Eigen::Vector3d& t_cam, const Eigen::Matrix3d& R_turn) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_turn * xr::render::kR_optical_view;
  T.translation() = t_cam;
  return T;
}

inline Eigen::Matrix3d rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

struct NamedPose {
  std::string name;
  Eigen::Isometry3d T_cam_eye;
};

/// Poses the geometry tests run: aligned, a head translation, identity (eye looking backwards
/// along −z of the camera), 180° roll, near-identity turn (1e-5 rad), and a 100° turn (rays
/// beyond 90°, and beyond 180° of field of view, for the fisheye lenses).
inline std::vector<NamedPose> testPoses() {
  const Eigen::Vector3d no_move = Eigen::Vector3d::Zero();
  const Eigen::Vector3d head_move(0.04, -0.03, 0.06);
  return {{"aligned", eyePose(no_move, Eigen::Matrix3d::Identity())},
          {"translated", eyePose(head_move, rotation(0.2, {1, 2, 0}))},
          {"identity", Eigen::Isometry3d::Identity()},
          {"roll180", eyePose(head_move, rotation(M_PI, {0, 0, 1}))},
          {"tiny_turn", eyePose(no_move, rotation(1e-5, {0, 1, 0}))},
          {"turn100", eyePose(head_move, rotation(100.0 * M_PI / 180.0, {0, 1, 0.1}))}};
}

}  // namespace telesphere::test
