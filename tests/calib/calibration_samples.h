// SPDX-License-Identifier: MIT
/// @brief Sample system calibrations for the file tests: a stereo pair of each model.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "calib/system_calibration.h"

namespace telesphere::test {

inline Eigen::Isometry3d pose(double tx, double ty, double tz, double rx, double ry, double rz) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() << tx, ty, tz;
  return T;
}

/// A stereo pair of `model` with awkward (non-round) numbers, as a calibration would give.
inline calib::SystemCalibration samplePair(const std::string& model, bool hand_eye = true) {
  Eigen::VectorXd p;
  if (model == "ds" || model == "eucm") {
    p.resize(6);
    p << 930.123456789012, 931.000000000001, 1919.4999999, 1079.51234, model == "ds" ? -0.1812345678901234 : 0.6123456789,
        model == "ds" ? 0.5912345678901234 : 1.0512345678;
  } else {
    p.resize(8);
    p << 1080.1, 1081.2, 1919.3, 1079.4, model == "kb4" ? 0.0201 : -0.2012345, 0.0051234, 0.00112, -0.0001234;
  }
  Eigen::VectorXd q = p;
  q[0] += 1.5;
  q[2] -= 2.25;
  calib::SystemCalibration c;
  c.cameras.push_back({"cam_l", *calib::GenericCamera::create(model, p), 3840, 2160});
  c.cameras.push_back({"cam_r", *calib::GenericCamera::create(model, q), 3840, 2160});
  c.T_cam_l_cam_r = pose(0.0641234567, -0.000123, 0.00051, 0.001, -0.02, 0.0031);
  if (hand_eye) {
    c.T_flange_cam_l = pose(0.05, -0.032, 0.11, -1.5707, 0.01, -1.5708);
    c.T_robot_mount = pose(0.3, 0.2, -0.1, 0, 0, 3.1415926);
    c.T_wrist_marker = pose(0, 0, 0.07, 3.14159, 0, 0.5);
  }
  return c;
}

inline void expectSameTransform(const std::optional<Eigen::Isometry3d>& a,
                                const std::optional<Eigen::Isometry3d>& b, const char* name) {
  ASSERT_EQ(a.has_value(), b.has_value()) << name;
  if (a) {
    EXPECT_LT((a->matrix() - b->matrix()).cwiseAbs().maxCoeff(), 1e-14) << name;
  }
}

/// Parameters compare exactly: the formats write 17 significant digits.
inline void expectSameCalibration(const calib::SystemCalibration& a,
                                  const calib::SystemCalibration& b, bool with_hand_eye = true) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (std::size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(a.cameras[i].label, b.cameras[i].label);
    EXPECT_EQ(a.cameras[i].camera.modelName(), b.cameras[i].camera.modelName());
    EXPECT_EQ(a.cameras[i].camera.params(), b.cameras[i].camera.params()) << "camera " << i;
    EXPECT_EQ(a.cameras[i].width, b.cameras[i].width);
    EXPECT_EQ(a.cameras[i].height, b.cameras[i].height);
  }
  expectSameTransform(a.T_cam_l_cam_r, b.T_cam_l_cam_r, "T_cam_l_cam_r");
  if (with_hand_eye) {
    expectSameTransform(a.T_flange_cam_l, b.T_flange_cam_l, "T_flange_cam_l");
    expectSameTransform(a.T_robot_mount, b.T_robot_mount, "T_robot_mount");
    expectSameTransform(a.T_wrist_marker, b.T_wrist_marker, "T_wrist_marker");
  }
}

}  // namespace telesphere::test
