// SPDX-License-Identifier: MIT
/// @brief What the sphere sweep does to its grid after matching (#35): tiles it could not match take
///        their confident neighbours' median, ring after ring, and a 3×3 median then removes lone
///        outliers. Linear in the grid's tiles: each ring visits only the tiles next to the last
///        one (the unseen back half of a fisheye's grid is about twenty rings deep).
#pragma once

#include <vector>

#include "xr/render/depth_proxy.h"

namespace telesphere::xr::depth {

/// Fills tiles of confidence 0 from the median of their confident 8-neighbours, repeatedly, then
/// any left with the median of all confident tiles (or leaves them when none is); then a 3×3
/// median over the grid (longitude wrapping, rows clamped at the poles). A median of an even count
/// is its upper middle value.
void fillAndSmooth(render::InverseDepthGrid& grid, const std::vector<float>& confidence);

}  // namespace telesphere::xr::depth
