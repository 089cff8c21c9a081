// SPDX-License-Identifier: MIT
/// @brief Poses on the link: Eigen isometries ↔ the schema's `Pose` (translation in metres, unit
///        quaternion). One place, so every sender and receiver agrees on the convention.
#pragma once

#include <Eigen/Geometry>
#include <limits>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link {

inline void toLinkPose(const Eigen::Isometry3d& T, proto::Pose* out) {
  const Eigen::Quaterniond q(T.rotation());
  out->set_tx(T.translation().x());
  out->set_ty(T.translation().y());
  out->set_tz(T.translation().z());
  out->set_qx(q.x());
  out->set_qy(q.y());
  out->set_qz(q.z());
  out->set_qw(q.w());
}

/// The quaternion is normalised; a zero one gives a NaN rotation, which every consumer's pose
/// check refuses (never a silent identity).
inline Eigen::Isometry3d fromLinkPose(const proto::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(p.tx(), p.ty(), p.tz());
  const Eigen::Quaterniond q(p.qw(), p.qx(), p.qy(), p.qz());
  const double n = q.norm();
  T.linear() = n > 0.0 ? Eigen::Quaterniond(q.coeffs() / n).toRotationMatrix()
                       : Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  return T;
}

}  // namespace telesphere::link
