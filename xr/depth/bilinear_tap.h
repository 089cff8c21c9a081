// SPDX-License-Identifier: MIT
/// @brief A bilinear sample of an 8-bit grey image at a position fixed in advance (#35): the
///        top-left pixel and the two weights, quantised to 1/256 of a pixel, so that taking the
///        sample is four byte loads and integer multiply-adds (no float position, rounding or
///        clamping per sample). The sphere sweep's tables hold one per sample position.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace telesphere::xr::depth {

struct BilinearTap {
  std::uint16_t x = 0, y = 0;    ///< the top-left pixel of the 2×2 block (pixel centres at integers)
  std::uint16_t wx = 0, wy = 0;  ///< weights of the right column and the bottom row, in 1/256 (0–256)
};

/// The tap at position `p` of an image `width` × `height` (at least 2 × 2, at most 65536 wide and
/// high); `p` inside [0, width − 1] × [0, height − 1].
inline BilinearTap bilinearTap(const Eigen::Vector2d& p, int width, int height) {
  // p is not negative, so truncating is flooring, and a weight rounds half up as std::lround does
  // (its fraction after truncating is exact; adding ½ first would round 0.5 − 2⁻⁵⁴ up): no library
  // call (std::floor and std::lround are calls on baseline x86-64, and the sweep makes taps for
  // every sample of every tile its earlier views look at).
  const int x0 = std::clamp(static_cast<int>(p.x()), 0, width - 2);
  const int y0 = std::clamp(static_cast<int>(p.y()), 0, height - 2);
  const auto weight = [](double f) {
    const double scaled = f * 256.0;
    const int whole = static_cast<int>(scaled);
    return static_cast<std::uint16_t>(std::clamp(whole + (scaled - whole >= 0.5 ? 1 : 0), 0, 256));
  };
  return {static_cast<std::uint16_t>(x0), static_cast<std::uint16_t>(y0), weight(p.x() - x0), weight(p.y() - y0)};
}

/// The grey value at the tap, in grey levels (0–255), from an image whose rows are `stride` bytes apart.
inline float tapGrey(const std::uint8_t* pixels, int stride, const BilinearTap& t) {
  const std::uint8_t* p = pixels + static_cast<std::ptrdiff_t>(t.y) * stride + t.x;
  const std::uint32_t wx = t.wx, wy = t.wy;
  const std::uint32_t top = p[0] * (256U - wx) + p[1] * wx;
  const std::uint32_t bottom = p[stride] * (256U - wx) + p[stride + 1] * wx;
  return static_cast<float>(top * (256U - wy) + bottom * wy) * (1.0F / 65536.0F);
}

}  // namespace telesphere::xr::depth
