// SPDX-License-Identifier: MIT
/// @brief The luma plane shrunk to the sphere sweep's working size (#35): the mean of each
///        factor × factor block, which maps like one pixel of the image at 1/factor
///        (calib::atResolution's convention, pixel centres at integers).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace telesphere::xr::depth {

/// The rounded mean of each factor × factor block of a width × height 8-bit plane (rows
/// `stride` bytes apart) into out (reused; width/factor × height/factor, rows tightly packed);
/// a partial block at the right or bottom edge is dropped. factor ≥ 1.
void boxDownscale(std::span<const std::uint8_t> plane, int width, int height, int stride, int factor,
                  std::vector<std::uint8_t>& out, int* out_width, int* out_height);

}  // namespace telesphere::xr::depth
