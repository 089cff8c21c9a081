// SPDX-License-Identifier: MIT
/// @brief The restart markers in a JPEG's entropy-coded data (RST0..RST7, 0xFFD0..0xFFD7 after the
///        SOS segment), one helper for the JPEG encoder's tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace telesphere::test {

/// How many restart markers the JPEG holds; −1 when it has no SOS segment.
inline int countRestartMarkers(const std::vector<std::uint8_t>& jpeg) {
  std::size_t i = 2;
  while (i + 4 <= jpeg.size() && !(jpeg[i] == 0xFF && jpeg[i + 1] == 0xDA))
    i += 2 + (static_cast<std::size_t>(jpeg[i + 2]) << 8 | jpeg[i + 3]);  // skip a header segment
  if (i + 4 > jpeg.size()) return -1;
  i += 2 + (static_cast<std::size_t>(jpeg[i + 2]) << 8 | jpeg[i + 3]);
  int n = 0;
  for (; i + 1 < jpeg.size(); ++i)
    if (jpeg[i] == 0xFF && jpeg[i + 1] >= 0xD0 && jpeg[i + 1] <= 0xD7) ++n;
  return n;
}

}  // namespace telesphere::test
