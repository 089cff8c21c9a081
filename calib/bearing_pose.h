// SPDX-License-Identifier: MIT
/// @brief Pose of a planar target from bearing vectors (unit rays in the camera frame), never
///        from pinhole-normalised points: rays at and beyond 90° off-axis (z ≤ 0) count like all
///        others. Direct linear transform of the plane-to-ray homography d ∝ [r1 r2 t]·(x, y, 1)
///        with constraints d × H·(x, y, 1) = 0, then the nearest rotation.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace telesphere::calib {

/// T_cam_target from ≥ 4 points p_target (metres, on the plane z = 0 of the target frame, not
/// all on one line) and their unit bearings d_cam (camera optical frame). Nothing when the
/// points are degenerate or the rays do not fit any pose in front of the camera.
std::optional<Eigen::Isometry3d> planarPoseFromBearings(const std::vector<Eigen::Vector3d>& p_target,
                                                        const std::vector<Eigen::Vector3d>& d_cam);

}  // namespace telesphere::calib
