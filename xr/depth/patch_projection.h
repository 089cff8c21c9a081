// SPDX-License-Identifier: MIT
/// @brief Where a tile's patch of sample directions lands in a camera that has moved (#35): the
///        sphere sweep's earlier views (sphere_sweep.h) have a motion that changes every frame, so
///        their sample positions cannot be tabled and are projected per frame. Projecting only the
///        patch's four corners and placing the samples between them (bilinear in the patch's
///        indices) takes 4 projections instead of n × n; tests/xr/test_patch_projection.cpp bounds
///        what that costs in pixels against projecting every sample.
#pragma once

#include <Eigen/Geometry>

#include "calib/generic_camera.h"

namespace telesphere::xr::depth {

/// The n × n directions `directions` (row-major, unit, in the reference camera's frame), each at
/// inverse depth `rho` (1/m), seen by `camera` at T_view_reference: their pixels into `px_out`
/// (n × n). `corners_only`: project the four corners and interpolate the rest. False where a
/// projected sample (every one, or a corner) does not project; pixels may lie outside the image.
bool projectPatch(const calib::GenericCamera& camera, const Eigen::Vector3f* directions, int n,
                  const Eigen::Isometry3d& T_view_reference, double rho, bool corners_only, Eigen::Vector2d* px_out);

}  // namespace telesphere::xr::depth
