// SPDX-License-Identifier: MIT
/// @brief Yaw, pitch and roll of an operator head pose, the way a supervisor reads them: the robot
///        reports them for a captured nominal pose and the console shows them live, so both use
///        this one definition.
///
/// Input: T_vr_hmd, the OpenXR view pose (view axes: x right, y up, −z forward) in a reference
/// space whose +y is up (STYLE.md §6). With f = −z_view (the gaze direction, VR frame):
///   yaw   = atan2(−f.x, −f.z)   turning left is positive; 0 looks along the space's −z;
///   pitch = asin(f.y)           looking up is positive;
///   roll  = rotation of the head's up axis about f, positive when the right ear goes down.
/// At |pitch| = 90° (looking straight up or down) the yaw is taken from the top of the head
/// instead of the gaze, roll is then 0.
/// Removing pitch and roll (the nominal pose, DESIGN.md §2) keeps exactly `yaw`.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace telesphere::link {

struct HeadAngles {
  double yaw = 0.0;    ///< rad
  double pitch = 0.0;  ///< rad
  double roll = 0.0;   ///< rad
};

inline HeadAngles headAnglesOf(const Eigen::Isometry3d& T_vr_hmd) {
  const Eigen::Matrix3d& R = T_vr_hmd.linear();
  const Eigen::Vector3d f = -R.col(2);  // gaze
  const Eigen::Vector3d u = R.col(1);   // top of the head
  const Eigen::Vector3d up_vr(0, 1, 0);
  HeadAngles a;
  a.pitch = std::asin(std::clamp(f.dot(up_vr), -1.0, 1.0));
  Eigen::Vector3d level = f - f.dot(up_vr) * up_vr;
  if (level.norm() < 1e-9) {
    // Straight down: the top of the head points where the gaze would be levelled; straight up:
    // the back of the head does.
    const Eigen::Vector3d top = f.y() < 0 ? u : Eigen::Vector3d(-u);
    level = top - top.dot(up_vr) * up_vr;
    a.yaw = std::atan2(-level.x(), -level.z());
    return a;
  }
  level.normalize();
  a.yaw = std::atan2(-level.x(), -level.z());
  const Eigen::Vector3d left = up_vr.cross(level).normalized();  // level left of the gaze
  const Eigen::Vector3d up_level = f.cross(left).normalized();   // up, in the plane ⟂ gaze
  a.roll = std::atan2(-u.dot(left), u.dot(up_level));
  return a;
}

/// T_vr_hmd with pitch and roll removed: turned by its yaw alone about +y, the position kept (the
/// nominal pose, DESIGN.md §2; the XR test scene's level frame). The one definition: straight up
/// and down take the yaw from the top of the head, as headAnglesOf does.
inline Eigen::Isometry3d withoutPitchAndRoll(const Eigen::Isometry3d& T_vr_hmd) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(headAnglesOf(T_vr_hmd).yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = T_vr_hmd.translation();
  return T;
}

/// The inverse for tests and scripted heads: yaw about +y, then pitch about the head's left
/// axis (nose up positive), then roll about the gaze (right ear down positive).
inline Eigen::Matrix3d headRotationOf(const HeadAngles& a) {
  return (Eigen::AngleAxisd(a.yaw, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.pitch, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(-a.roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

}  // namespace telesphere::link
