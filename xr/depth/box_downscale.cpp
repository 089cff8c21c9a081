// SPDX-License-Identifier: MIT
/// @brief boxDownscale: block means of an 8-bit plane.
#include "xr/depth/box_downscale.h"

#include <algorithm>

namespace telesphere::xr::depth {

void boxDownscale(std::span<const std::uint8_t> plane, int width, int height, int stride, int factor,
                  std::vector<std::uint8_t>& out, int* out_width, int* out_height) {
  factor = std::max(1, factor);
  const int w = width / factor, h = height / factor;
  out.assign(static_cast<std::size_t>(w) * h, 0);
  std::vector<std::uint32_t> sums(static_cast<std::size_t>(w));
  const std::uint32_t n = static_cast<std::uint32_t>(factor * factor);
  for (int by = 0; by < h; ++by) {
    std::fill(sums.begin(), sums.end(), 0u);
    for (int r = 0; r < factor; ++r) {
      const std::uint8_t* row = plane.data() + static_cast<std::size_t>(by * factor + r) * stride;
      for (int bx = 0; bx < w; ++bx) {
        std::uint32_t s = 0;
        for (int c = 0; c < factor; ++c) s += row[bx * factor + c];
        sums[static_cast<std::size_t>(bx)] += s;
      }
    }
    for (int bx = 0; bx < w; ++bx)
      out[static_cast<std::size_t>(by) * w + bx] = static_cast<std::uint8_t>((sums[static_cast<std::size_t>(bx)] + n / 2) / n);
  }
  *out_width = w;
  *out_height = h;
}

}  // namespace telesphere::xr::depth
