// SPDX-License-Identifier: MIT
/// @brief Inverse depth around one camera from the stereo pair, on the fisheye images as they are
///        (#35, DESIGN.md §11): a sphere sweep. For each tile of an InverseDepthGrid that the
///        reference camera sees, a patch of sample directions is looked up in the reference image
///        and, for each inverse-depth hypothesis ρ, where those directions at depth 1/ρ fall in the
///        other image (∝ R·u + ρ·t: ρ = 0 is a point at infinity); the hypothesis whose patch
///        correlates best (zero-mean normalised cross-correlation) wins, refined by a parabola
///        through its neighbours. Every sample position is computed once, at construction, for
///        the calibration: per frame only bilinear samples and sums remain. Tiles without texture
///        or without a clear best are left unconfident, then filled from their neighbours; a 3×3
///        median smooths the grid.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "calib/generic_camera.h"
#include "xr/depth/bilinear_tap.h"
#include "xr/depth/patch_sums.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::xr::depth {

/// A grey image (8-bit, rows `stride` bytes apart) the sweep reads; the pixels are borrowed.
struct GreyImage {
  const std::uint8_t* pixels = nullptr;
  int width = 0, height = 0, stride = 0;
};

struct SphereSweepOptions {
  double tile_deg = 4.0;         ///< the grid's tiles (a divisor of 180)
  double min_depth_m = 0.25;     ///< the nearest hypothesis
  int hypotheses = 48;           ///< inverse depths from 0 to 1/min_depth_m, evenly spaced
  int samples_per_side = 5;      ///< a tile's patch: n × n directions spread over it
  double min_texture = 2.0;      ///< grey-level standard deviation below which a tile is not matched
  double min_correlation = 0.7;  ///< the best hypothesis's ZNCC below which a tile is not trusted
  /// The best must beat every hypothesis beyond its neighbours by this much in 1 − ZNCC (a
  /// repetitive pattern matches at several depths and is left unconfident).
  double min_margin = 0.05;
  /// The correlation sums eight samples a step (AVX2, xr/depth/patch_sums.h) where the CPU can;
  /// false: one at a time (the reference the benchmark and the tests compare with).
  bool simd = true;
};

/// One sweep's output: the grid (every tile filled) and how far each tile's value is measured.
struct SweepResult {
  render::InverseDepthGrid inverse_depth{4.0};
  /// Per tile (the grid's order): the best ZNCC where the tile was matched and trusted, 0 where
  /// its value was filled from neighbours.
  std::vector<float> confidence;
  int tiles_seen = 0;     ///< tiles whose patch lies inside both images at some depth
  int tiles_matched = 0;  ///< of those, trusted
};

class SphereSweep {
 public:
  /// `reference` and `other`: the two cameras' models at the size of the images the sweep will
  /// get; `T_other_reference` maps points from the reference camera's frame into the other's.
  SphereSweep(const calib::GenericCamera& reference, int reference_width, int reference_height,
              const calib::GenericCamera& other, int other_width, int other_height,
              const Eigen::Isometry3d& T_other_reference, SphereSweepOptions options = {});

  /// The grid for one stereo pair (images of the sizes given at construction). Empty images, or
  /// other sizes, give a grid of the farthest hypothesis with no tile matched.
  SweepResult estimate(const GreyImage& reference, const GreyImage& other) const;

  const SphereSweepOptions& options() const { return options_; }
  /// Inverse depth (1/m) of hypothesis k.
  double hypothesis(int k) const;
  /// Bytes of precomputed sample positions.
  std::size_t tableBytes() const;

 private:
  struct Tile {
    int row = 0, col = 0;
    std::size_t first = 0;     ///< index of its first reference sample in reference_px_
    std::size_t other = 0;     ///< index of its first other sample in other_px_ (samples × hypotheses)
    std::vector<bool> usable;  ///< per hypothesis: every sample inside the other image
    bool gather_safe = true;   ///< every other sample may be read four bytes wide (patch_sums.h)
  };
  SphereSweepOptions options_;
  int reference_width_, reference_height_, other_width_, other_height_;
  int samples_ = 0;  ///< per tile
  std::vector<Tile> tiles_;
  std::vector<BilinearTap> reference_px_;
  std::vector<BilinearTap> other_px_;  ///< per tile: hypothesis-major, then sample
};

/// Fills tiles of confidence 0 from the median of their confident 8-neighbours, repeatedly, then
/// any left with the median of all confident tiles (or leaves them when none is); then a 3×3
/// median over the grid (longitude wrapping). What SphereSweep::estimate does after matching.
void fillAndSmooth(render::InverseDepthGrid& grid, const std::vector<float>& confidence);

}  // namespace telesphere::xr::depth
