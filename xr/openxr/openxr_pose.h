// SPDX-License-Identifier: MIT
/// @brief Conversions at the OpenXR boundary (STYLE.md §6): XrPosef → Eigen isometry (the pose
///        of a space in its base space, T_base_space), XrFovf → Fov, the HMD pose as the eyes'
///        midpoint, and the validity test of a located view.
#pragma once

#include <openxr/openxr.h>

#include <Eigen/Geometry>
#include <cmath>

#include "xr/render/eye_view.h"

namespace telesphere::xr::openxr {

/// T_base_space from the XrPosef that xrLocateSpace/xrLocateViews returned for `space` in `base`
/// (maps points from the located space into the base space). The quaternion is normalised; a
/// zero or non-finite quaternion gives a non-finite matrix, which checkPose() refuses.
inline Eigen::Isometry3d isometryFromXrPose(const XrPosef& pose) {
  Eigen::Quaterniond q(pose.orientation.w, pose.orientation.x, pose.orientation.y,
                       pose.orientation.z);
  const double n = q.norm();
  q.coeffs() /= n;  // n == 0 → NaN: refused downstream, never rendered
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() << pose.position.x, pose.position.y, pose.position.z;
  return T;
}

inline render::Fov fovFromXr(const XrFovf& fov) {
  return render::Fov{fov.angleLeft, fov.angleRight, fov.angleUp, fov.angleDown};
}

/// The midpoint pose of two eyes (positions averaged, orientation slerped halfway): the HMD
/// pose T_vr_hmd as far as the views tell.
inline Eigen::Isometry3d midpointPose(const Eigen::Isometry3d& T_vr_eye_l,
                                      const Eigen::Isometry3d& T_vr_eye_r) {
  const Eigen::Quaterniond q_l(T_vr_eye_l.linear()), q_r(T_vr_eye_r.linear());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q_l.slerp(0.5, q_r).normalized().toRotationMatrix();
  T.translation() = 0.5 * (T_vr_eye_l.translation() + T_vr_eye_r.translation());
  return T;
}

/// A view is rendered only with both orientation and position valid (STYLE.md §14).
inline bool viewPoseValid(XrViewStateFlags flags) {
  return (flags & XR_VIEW_STATE_ORIENTATION_VALID_BIT) != 0 &&
         (flags & XR_VIEW_STATE_POSITION_VALID_BIT) != 0;
}

}  // namespace telesphere::xr::openxr
