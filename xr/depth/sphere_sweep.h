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
///        median smooths the grid (fill_and_smooth.h).
///
///        More baselines from the arm's motion: a pattern repeating along the pair's baseline
///        (stripes, a grille, shelves) matches at several depths, spaced by the pattern's period
///        over the baseline, and no tile size or smoothing decides between them (xr/README.md). The
///        reference camera's own images from earlier poses, where the arm has moved it since, see
///        those aliases at other depths (other baselines, other spacings: multi-baseline stereo,
///        Okutomi & Kanade 1993). A tile the pair leaves ambiguous, or whose pair cost has another
///        local minimum near its best and where the widest view does not correlate at the pair's choice,
///        takes the candidate (a local minimum of the pair's cost) where the views' summed cost is
///        clearly lowest, if one is. Only views in which the patch's texture moves with depth take
///        part. The views' sample positions depend on the motion, so they are projected per frame,
///        for those tiles and candidates only (patch_projection.h).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "calib/generic_camera.h"
#include "xr/depth/bilinear_tap.h"
#include "xr/depth/fill_and_smooth.h"
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
  /// With earlier views: a tile's candidates are the local minima of its pair cost
  /// within this of its best (1 − ZNCC). Generous: a pattern's correlation peak can be narrower
  /// than a hypothesis step, so the true depth can score far worse than an alias that a
  /// hypothesis happens to hit.
  double motion_candidate_window = 0.5;
  /// An earlier view takes part for a tile only where this fraction of the patch's grey gradient
  /// energy lies along the direction its parallax moves the tile (a motion along stripes cannot
  /// tell their depths apart, and its costs then favour no parallax at all).
  double motion_min_gradient_fraction = 0.25;
  /// The earlier views' sample positions from each patch's four corners (xr/depth/patch_projection.h);
  /// false: every sample projected.
  bool motion_corner_projection = true;
  /// The correlation sums eight samples a step (AVX2, xr/depth/patch_sums.h) where the CPU can;
  /// false: one at a time (the reference the benchmark and the tests compare with).
  bool simd = true;
};

/// The reference camera's own image, captured earlier from another pose (the arm has moved it
/// since): another baseline for the tiles the pair leaves ambiguous. The scene is assumed still
/// between the captures; where a view's patch does not correlate at the chosen depth, the tile
/// keeps the pair's outcome. (A pattern that itself moved by a multiple of its alias spacing
/// between the captures cannot be told from a still one.)
struct EarlierView {
  GreyImage image;  ///< the size of the reference image
  /// Maps points from the reference camera's frame (now) into its frame at the earlier capture:
  /// T_robot_cam(earlier)⁻¹ · T_robot_cam(now).
  Eigen::Isometry3d T_earlier_reference = Eigen::Isometry3d::Identity();
};

/// One sweep's output: the grid (every tile filled) and how far each tile's value is measured.
struct SweepResult {
  render::InverseDepthGrid inverse_depth{4.0};
  /// Per tile (the grid's order): the best ZNCC where the tile was matched and trusted, 0 where
  /// its value was filled from neighbours.
  std::vector<float> confidence;
  int tiles_seen = 0;     ///< tiles whose patch lies inside both images at some depth
  int tiles_matched = 0;  ///< of those, trusted
  /// Of the tiles seen, textured and correlated but with another depth within the margin (a
  /// repetitive pattern): ambiguous on the pair alone, whether or not the earlier view decided them.
  int tiles_ambiguous = 0;
  /// Tiles whose depth the earlier views decided (counted as matched): ambiguous ones, and ones
  /// whose pair cost has another local minimum within the candidate window.
  int tiles_decided_by_motion = 0;
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
  /// With `earlier` views (images the reference's size; others are ignored): the ambiguous tiles
  /// also from those views. A matched tile is checked against the one whose camera centre lies
  /// farthest across the optical axis.
  SweepResult estimate(const GreyImage& reference, const GreyImage& other, const std::vector<EarlierView>& earlier = {}) const;

  /// estimate() in its three steps, for the pair's costs from elsewhere (the GPU: gpu_sweep_costs.h).
  /// The reference image's side: each tile's (the sweep's order) mean-free patch, its Σa², and
  /// whether it has texture enough to match (σ ≥ min_texture).
  struct ReferencePatches {
    std::vector<float> a;                ///< per tile, per sample
    std::vector<float> sum_aa;           ///< per tile
    std::vector<std::uint8_t> textured;  ///< per tile
  };
  /// Whether images of these sizes can be swept (those given at construction, at least 2 × 2,
  /// rows at least an image wide).
  bool accepts(const GreyImage& reference, const GreyImage& other) const;
  /// Whether patches are this sweep's (one a tile, its samples).
  bool fits(const ReferencePatches& patches) const;
  /// Empty for an image of another size.
  ReferencePatches referencePatches(const GreyImage& reference) const;
  /// The same into `out`, reusing its memory.
  void referencePatches(const GreyImage& reference, ReferencePatches& out) const;
  /// The pair's cost volume: per tile, per hypothesis, 1 − ZNCC; infinity for tiles without
  /// texture, hypotheses whose patch leaves the other image, and all of an image of another size.
  std::vector<float> pairCosts(const ReferencePatches& patches, const GreyImage& other) const;
  void pairCosts(const ReferencePatches& patches, const GreyImage& other, std::vector<float>& out) const;
  /// The grid from a cost volume as pairCosts gives it (costs of unusable hypotheses are ignored,
  /// whatever they hold). A reference image, patches or costs of another size give a grid with no
  /// tile matched.
  SweepResult decide(const GreyImage& reference, const ReferencePatches& patches, const std::vector<float>& costs,
                     const std::vector<EarlierView>& earlier = {}) const;
  int tileCount() const { return static_cast<int>(tiles_.size()); }
  int otherWidth() const { return other_width_; }
  int otherHeight() const { return other_height_; }
  int samplesPerTile() const { return samples_; }
  /// The other image's taps: per tile, hypothesis-major, then sample.
  const std::vector<BilinearTap>& otherTaps() const { return other_px_; }

  const SphereSweepOptions& options() const { return options_; }
  /// Inverse depth (1/m) of hypothesis k.
  double hypothesis(int k) const;
  /// Bytes of precomputed sample positions.
  std::size_t tableBytes() const;

 private:
  struct Tile {
    int row = 0, col = 0;
    std::size_t first = 0;     ///< index of its first reference sample in reference_px_ and directions_
    std::size_t other = 0;     ///< index of its first other sample in other_px_ (samples × hypotheses)
    std::vector<std::uint8_t> usable;  ///< per hypothesis, 1: every sample inside the other image
    bool gather_safe = true;   ///< every other sample may be read four bytes wide (patch_sums.h)
  };
  /// Whether hypothesis k is a candidate: a local minimum of the pair's cost within the candidate
  /// window of its best.
  bool isCandidate(const std::vector<float>& cost, int k, int best) const;
  /// Whether the pair cost has a candidate beyond `best`'s neighbours.
  bool hasOtherCandidate(const std::vector<float>& cost, int best) const;
  struct Decided {
    double rho = 0;         ///< 1/m
    float confidence = 0;   ///< the earlier views' mean ZNCC there
  };
  /// The views in which the tile's texture moves with depth (appended to `informative`): where enough
  /// of the patch's grey gradient energy lies along the direction the view's parallax moves the tile.
  void informativeViews(const Tile& tile, const GreyImage& reference, const std::vector<EarlierView>& earlier,
                        std::vector<EarlierView>& informative) const;
  /// Decides a tile from the earlier views: at each candidate of the pair's `cost`, the summed cost
  /// of the views that see the patch at every candidate; the candidate where it is lowest, if it
  /// beats the others by the margin and each of those views correlates there.
  std::optional<Decided> resolveWithEarlier(const Tile& tile, const float* a, float sum_aa, const std::vector<float>& cost,
                                            int best, const std::vector<EarlierView>& earlier) const;
  /// 1 − ZNCC of the tile's patch (mean-free `a`) against `image` where the tile's directions at
  /// inverse depth `rho` fall in `camera` (∝ R·d + ρ·t); infinity where a sample falls outside.
  float projectedCost(const Tile& tile, const float* a, float sum_aa, const calib::GenericCamera& camera,
                      const Eigen::Isometry3d& T_view_reference, double rho, const GreyImage& image) const;

  SphereSweepOptions options_;
  calib::GenericCamera reference_;
  int reference_width_, reference_height_, other_width_, other_height_;
  int samples_ = 0;  ///< per tile
  std::vector<Tile> tiles_;
  std::vector<BilinearTap> reference_px_;
  std::vector<Eigen::Vector3f> directions_;  ///< per reference sample: its direction (the earlier view projects it)
  std::vector<BilinearTap> other_px_;  ///< per tile: hypothesis-major, then sample
};

}  // namespace telesphere::xr::depth
