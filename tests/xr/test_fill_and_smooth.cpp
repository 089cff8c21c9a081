// SPDX-License-Identifier: MIT
/// @brief fillAndSmooth (xr/depth/fill_and_smooth.h): holes take their neighbours' median, a lone
///        outlier goes, the longitude seam is no border; and on seeded random grids (values with
///        and without ties, scattered holes, a fisheye's unseen back half, a single known tile,
///        nothing known) it gives exactly what the plain definition gives: every unknown tile
///        scanned each ring, each window sorted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "xr/depth/fill_and_smooth.h"

namespace telesphere::xr {
namespace {

/// The definition, as slowly as it reads: each ring scans the whole grid for unknown tiles with a
/// known neighbour; each median sorts its values.
void fillAndSmoothByDefinition(render::InverseDepthGrid& grid, const std::vector<float>& confidence) {
  const int rows = grid.rows(), cols = grid.cols();
  const auto medianOf = [](std::vector<float> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::vector<char> known(confidence.size());
  std::vector<float> all_known;
  for (std::size_t i = 0; i < confidence.size(); ++i) {
    known[i] = confidence[i] > 0.0F;
    if (known[i]) all_known.push_back(grid.data()[i]);
  }
  if (all_known.empty()) return;
  for (bool grew = true; grew;) {
    grew = false;
    std::vector<std::pair<std::size_t, float>> filled;
    for (int row = 0; row < rows; ++row)
      for (int col = 0; col < cols; ++col) {
        const std::size_t i = static_cast<std::size_t>(row) * cols + col;
        if (known[i]) continue;
        std::vector<float> neighbours;
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int r = row + dr, c = (col + dc + cols) % cols;
            if ((dr || dc) && r >= 0 && r < rows && known[static_cast<std::size_t>(r) * cols + c]) neighbours.push_back(grid.at(r, c));
          }
        if (!neighbours.empty()) filled.emplace_back(i, medianOf(neighbours));
      }
    for (const auto& [i, value] : filled) {
      grid.at(static_cast<int>(i) / cols, static_cast<int>(i) % cols) = value;
      known[i] = 1;
      grew = true;
    }
  }
  for (std::size_t i = 0; i < known.size(); ++i)
    if (!known[i]) grid.at(static_cast<int>(i) / cols, static_cast<int>(i) % cols) = medianOf(all_known);
  const render::InverseDepthGrid before = grid;
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      std::vector<float> window;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) window.push_back(before.at(std::clamp(row + dr, 0, rows - 1), (col + dc + cols) % cols));
      grid.at(row, col) = medianOf(window);
    }
}

TEST(FillAndSmooth, HolesTakeTheirNeighboursAndALoneOutlierGoes) {
  render::InverseDepthGrid grid(10.0, 0.5F);  // 18 × 36 tiles
  std::vector<float> confidence(static_cast<std::size_t>(grid.rows()) * grid.cols(), 1.0F);
  const auto at = [&](int row, int col) -> float& { return confidence[static_cast<std::size_t>(row) * grid.cols() + col]; };
  // A hole of 3 × 3 unconfident tiles (their values junk) in a region of 2 1/m, across the seam.
  for (int row = 5; row <= 12; ++row)
    for (int col : {33, 34, 35, 0, 1, 2, 3})
      grid.at(row, col) = 2.0F;
  for (int row = 8; row <= 10; ++row)
    for (int col : {35, 0, 1}) {
      grid.at(row, col) = 99.0F;
      at(row, col) = 0.0F;
    }
  // A lone outlier elsewhere.
  grid.at(3, 18) = 7.0F;
  depth::fillAndSmooth(grid, confidence);
  for (int row = 8; row <= 10; ++row)
    for (int col : {35, 0, 1}) EXPECT_FLOAT_EQ(grid.at(row, col), 2.0F) << row << "," << col;
  EXPECT_FLOAT_EQ(grid.at(3, 18), 0.5F);
  EXPECT_FLOAT_EQ(grid.at(0, 0), 0.5F);
}

TEST(FillAndSmooth, GivesWhatItsDefinitionGivesOnSeededRandomGrids) {
  std::mt19937 random(20261129);
  enum class Holes { kScattered, kBackHalf, kOneKnown, kNoneKnown };
  int grids = 0;
  for (const double tile_deg : {4.0, 10.0, 90.0})
    for (const bool ties : {false, true})
      for (const Holes holes : {Holes::kScattered, Holes::kBackHalf, Holes::kOneKnown, Holes::kNoneKnown})
        for (int repeat = 0; repeat < 3; ++repeat) {
          render::InverseDepthGrid grid(tile_deg, 0.0F);
          const int rows = grid.rows(), cols = grid.cols();
          std::vector<float> confidence(static_cast<std::size_t>(rows) * cols, 0.0F);
          std::uniform_real_distribution<float> value(0.0F, 4.0F);
          std::uniform_int_distribution<int> level(0, 3);
          std::bernoulli_distribution hole(0.4);
          for (int row = 0; row < rows; ++row)
            for (int col = 0; col < cols; ++col) {
              grid.at(row, col) = ties ? 0.5F * static_cast<float>(level(random)) : value(random);
              const double longitude_deg = -180.0 + (col + 0.5) * tile_deg;
              bool known = true;
              if (holes == Holes::kScattered) known = !hole(random);
              if (holes == Holes::kBackHalf) known = std::abs(longitude_deg) < 95.0 && !hole(random);
              if (holes == Holes::kOneKnown) known = row == rows / 2 && col == cols / 3;
              if (holes == Holes::kNoneKnown) known = false;
              confidence[static_cast<std::size_t>(row) * cols + col] = known ? 0.9F : 0.0F;
            }
          render::InverseDepthGrid expected = grid;
          fillAndSmoothByDefinition(expected, confidence);
          depth::fillAndSmooth(grid, confidence);
          int differing = 0;
          for (int row = 0; row < rows; ++row)
            for (int col = 0; col < cols; ++col) differing += grid.at(row, col) != expected.at(row, col);
          EXPECT_EQ(differing, 0) << "tiles " << tile_deg << " deg, ties " << ties << ", holes " << static_cast<int>(holes);
          ++grids;
        }
  EXPECT_EQ(grids, 72);
}

}  // namespace
}  // namespace telesphere::xr
