// SPDX-License-Identifier: MIT
/// @brief concealRows: row copies plane by plane.
#include "xr/video/lost_row_concealment.h"

#include <algorithm>
#include <cstring>

namespace telesphere::xr::video {
namespace {

void copyRows(std::span<const std::uint8_t> from, std::span<const std::uint8_t> to, int width, int first, int end) {
  if (from.empty() || to.empty() || end <= first) return;
  const std::size_t begin = static_cast<std::size_t>(first) * static_cast<std::size_t>(width);
  const std::size_t bytes = static_cast<std::size_t>(end - first) * static_cast<std::size_t>(width);
  if (begin + bytes > from.size() || begin + bytes > to.size()) return;
  // Not shared yet (see the header): writing through the span's pointer is the decoder's right.
  std::memcpy(const_cast<std::uint8_t*>(to.data()) + begin, from.data() + begin, bytes);
}

}  // namespace

std::pair<int, int> concealRows(const render::YuvPlanes& target, const render::YuvPlanes* previous,
                                const std::vector<std::pair<int, int>>& lost) {
  int painted = 0, grey = 0;
  const bool usable = previous && previous->layout() == target.layout() && previous->subsampling == target.subsampling;
  for (auto [first, end] : lost) {
    first = std::clamp(first, 0, target.height);
    end = std::clamp(end, first, target.height);
    if (end == first) continue;
    if (!usable) {
      grey += end - first;
      continue;
    }
    copyRows(previous->yPlane(), target.yPlane(), target.width, first, end);
    if (target.chroma_height > 0 && target.height > 0) {
      const int c_first = first * target.chroma_height / target.height;
      const int c_end = (end * target.chroma_height + target.height - 1) / target.height;
      copyRows(previous->uPlane(), target.uPlane(), target.chroma_width, c_first, c_end);
      copyRows(previous->vPlane(), target.vPlane(), target.chroma_width, c_first, c_end);
    }
    painted += end - first;
  }
  return {painted, grey};
}

}  // namespace telesphere::xr::video
