// SPDX-License-Identifier: MIT
/// @brief fillAndSmooth: the ring-by-ring fill over the tiles next to the last ring, and the 3×3
///        median by a fixed network of compare-exchanges.
#include "xr/depth/fill_and_smooth.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>

namespace telesphere::xr::depth {
namespace {

float median(std::vector<float>& v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// The median of nine values: nineteen compare-exchanges (Paeth's network, Graphics Gems).
float median9(std::array<float, 9> p) {
  const auto sort2 = [&](int a, int b) {  // as `if (p[b] < p[a]) swap`, without a branch
    const float low = std::min(p[a], p[b]), high = std::max(p[b], p[a]);
    p[a] = low;
    p[b] = high;
  };
  sort2(1, 2), sort2(4, 5), sort2(7, 8), sort2(0, 1), sort2(3, 4), sort2(6, 7), sort2(1, 2), sort2(4, 5), sort2(7, 8);
  sort2(0, 3), sort2(5, 8), sort2(4, 7), sort2(3, 6), sort2(1, 4), sort2(2, 5), sort2(4, 7), sort2(4, 2), sort2(6, 4);
  sort2(4, 2);
  return p[4];
}

}  // namespace

void fillAndSmooth(render::InverseDepthGrid& grid, const std::vector<float>& confidence) {
  const int rows = grid.rows(), cols = grid.cols();
  const std::size_t tiles = static_cast<std::size_t>(rows) * cols;
  std::vector<char> known(tiles), queued(tiles);
  std::vector<float> all_known;
  for (std::size_t i = 0; i < tiles; ++i) {
    known[i] = confidence[i] > 0.0F;
    if (known[i]) all_known.push_back(grid.data()[i]);
  }
  if (all_known.empty()) return;
  const float fallback = median(all_known);
  // The 8-neighbours of tile i (rows end at the poles, longitude wraps). One division a tile, none
  // a neighbour: a modulo per neighbour cost more than everything else here.
  const auto forNeighbours = [&](std::size_t i, auto&& visit) {
    const int row = static_cast<int>(i / cols), col = static_cast<int>(i - static_cast<std::size_t>(row) * cols);
    const int neighbour_cols[3] = {col == 0 ? cols - 1 : col - 1, col, col + 1 == cols ? 0 : col + 1};
    for (int dr = -1; dr <= 1; ++dr) {
      const int r = row + dr;
      if (r < 0 || r >= rows) continue;
      for (int dc = -1; dc <= 1; ++dc)
        if (dr || dc) visit(static_cast<std::size_t>(r) * cols + neighbour_cols[dc + 1]);
    }
  };
  // Grow the known region a ring at a time: a hole takes the median of its known neighbours. The
  // ring is every unknown tile next to a known one; the next ring, the unknown tiles next to it.
  std::vector<std::size_t> ring, next;
  for (std::size_t i = 0; i < tiles; ++i) {
    if (known[i]) continue;
    bool next_to_known = false;
    forNeighbours(i, [&](std::size_t j) { next_to_known = next_to_known || known[j]; });
    if (next_to_known) {
      ring.push_back(i);
      queued[i] = 1;
    }
  }
  std::vector<std::pair<std::size_t, float>> filled;
  while (!ring.empty()) {
    filled.clear();
    for (const std::size_t i : ring) {
      // At most eight known neighbours, sorted in place; the median is the upper middle one.
      std::array<float, 8> neighbours{};
      int count = 0;
      forNeighbours(i, [&](std::size_t j) {
        if (!known[j]) return;
        const float value = grid.data()[j];
        int k = count++;
        for (; k > 0 && value < neighbours[k - 1]; --k) neighbours[k] = neighbours[k - 1];
        neighbours[k] = value;
      });
      filled.emplace_back(i, neighbours[count / 2]);
    }
    for (const auto& [i, value] : filled) {
      grid.at(static_cast<int>(i / cols), static_cast<int>(i % cols)) = value;
      known[i] = 1;
    }
    next.clear();
    for (const auto& filled_tile : filled)
      forNeighbours(filled_tile.first, [&](std::size_t j) {
        if (!known[j] && !queued[j]) {
          queued[j] = 1;
          next.push_back(j);
        }
      });
    std::swap(ring, next);
  }
  for (std::size_t i = 0; i < tiles; ++i)
    if (!known[i]) grid.at(static_cast<int>(i / cols), static_cast<int>(i % cols)) = fallback;
  // 3×3 median (rows clamped at the poles, longitude wrapping); no division per tile (the modulo
  // for the wrap cost as much as the medians).
  const render::InverseDepthGrid before = grid;
  std::array<float, 9> window{};
  for (int row = 0; row < rows; ++row) {
    const int window_rows[3] = {std::max(row - 1, 0), row, std::min(row + 1, rows - 1)};
    for (int col = 0; col < cols; ++col) {
      const int window_cols[3] = {col == 0 ? cols - 1 : col - 1, col, col + 1 == cols ? 0 : col + 1};
      int w = 0;
      for (const int r : window_rows)
        for (const int c : window_cols) window[w++] = before.at(r, c);
      grid.at(row, col) = median9(window);
    }
  }
}

}  // namespace telesphere::xr::depth
