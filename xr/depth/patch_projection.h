// SPDX-License-Identifier: MIT
/// @brief Where a tile's patch of sample directions lands in a camera that has moved (#35): the
///        sphere sweep's earlier views (sphere_sweep.h) have a motion that changes every frame, so
///        their sample positions cannot be tabled and are projected per frame. Projecting only the
///        patch's four corners and placing the samples between them (bilinear in the patch's
///        indices) takes 4 projections instead of n × n; tests/xr/test_patch_projection.cpp bounds
///        what that costs in pixels against projecting every sample. The samples' bilinear taps
///        then come straight from the corners (tapsBetweenCorners), four at a step where the CPU
///        has AVX2, each equal to the tap of the interpolated position, and so do the patch's sums
///        (patchSumsBetweenCorners), eight taps a step without writing them out.
#pragma once

#include <Eigen/Geometry>

#include "calib/generic_camera.h"
#include "xr/depth/bilinear_tap.h"
#include "xr/depth/patch_sums.h"

namespace telesphere::xr::depth {

/// A patch's four corner samples in an image (pixels): rows 0 and n − 1, columns 0 and n − 1.
struct PatchCorners {
  Eigen::Vector2d p00, p01, p10, p11;
};

/// Sample (i, j) of an n × n patch (n ≥ 2) placed between its corners, bilinear in i/(n − 1) and
/// j/(n − 1). The one formula every placement uses (tapsBetweenCorners computes it too, operation
/// for operation).
inline Eigen::Vector2d betweenCorners(const PatchCorners& c, int n, int i, int j) {
  const double u = static_cast<double>(i) / (n - 1), v = static_cast<double>(j) / (n - 1);
  return (1 - u) * ((1 - v) * c.p00 + v * c.p01) + u * ((1 - v) * c.p10 + v * c.p11);
}

/// The corners of the n × n directions `directions` (row-major, unit, in the reference camera's
/// frame), each at inverse depth `rho` (1/m), seen by `camera` at T_view_reference. False where a
/// corner does not project; pixels may lie outside the image.
bool projectPatchCorners(const calib::GenericCamera& camera, const Eigen::Vector3f* directions, int n,
                         const Eigen::Isometry3d& T_view_reference, double rho, PatchCorners& out);

/// The n × n directions `directions` (row-major, unit, in the reference camera's frame), each at
/// inverse depth `rho` (1/m), seen by `camera` at T_view_reference: their pixels into `px_out`
/// (n × n). `corners_only`: project the four corners and interpolate the rest (betweenCorners). False
/// where a projected sample (every one, or a corner) does not project; pixels may lie outside the image.
bool projectPatch(const calib::GenericCamera& camera, const Eigen::Vector3f* directions, int n,
                  const Eigen::Isometry3d& T_view_reference, double rho, bool corners_only, Eigen::Vector2d* px_out);

/// The n × n taps (n ≥ 2) of a patch between `corners`, into `out` (n × n, row-major): each
/// bilinearTap(betweenCorners(corners, n, i, j), width, height), to the bit. The corners must lie
/// inside [0, width − 1] × [0, height − 1] (then every sample does, up to rounding that the tap's
/// clamp absorbs as bilinearTap's does). `simd`: four samples a step where the CPU has AVX2.
void tapsBetweenCorners(const PatchCorners& corners, int n, int width, int height, BilinearTap* out, bool simd = true);

/// The patch sums (patch_sums.h) over those taps of an image `width` × `height` whose rows are
/// `stride` bytes apart, against the reference patch `a` (n × n): to the bit what patchSums gives
/// over tapsBetweenCorners's taps, eight a step only where `simd` and every tap is gatherSafe. Where
/// the CPU has AVX2 the taps are made in registers and summed at once, not written out first.
PatchSums patchSumsBetweenCorners(const std::uint8_t* pixels, int stride, int width, int height, const PatchCorners& corners, int n,
                                  const float* a, bool simd = true);

}  // namespace telesphere::xr::depth
