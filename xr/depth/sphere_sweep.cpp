// SPDX-License-Identifier: MIT
/// @brief The sphere sweep: sample tables (bilinear taps) at construction, correlation per tile and hypothesis per
///        frame, then holes filled and a 3×3 median (fill_and_smooth.cpp).
#include "xr/depth/sphere_sweep.h"

#include "xr/depth/patch_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace telesphere::xr::depth {
namespace {

bool inside(const Eigen::Vector2d& px, int width, int height) {
  return px.x() >= 0.0 && px.y() >= 0.0 && px.x() <= width - 1.0 && px.y() <= height - 1.0;
}

}  // namespace

SphereSweep::SphereSweep(const calib::GenericCamera& reference, int reference_width, int reference_height,
                         const calib::GenericCamera& other, int other_width, int other_height,
                         const Eigen::Isometry3d& T_other_reference, SphereSweepOptions options)
    : options_(options),
      reference_(reference),
      reference_width_(reference_width),
      reference_height_(reference_height),
      other_width_(other_width),
      other_height_(other_height) {
  options_.hypotheses = std::max(options_.hypotheses, 3);
  options_.samples_per_side = std::max(options_.samples_per_side, 2);
  samples_ = options_.samples_per_side * options_.samples_per_side;
  const render::InverseDepthGrid grid(options_.tile_deg);  // throws on a tile size that does not fit
  const Eigen::Matrix3d R = T_other_reference.linear();
  const Eigen::Vector3d t = T_other_reference.translation();
  const int n = options_.samples_per_side;
  if (std::max({reference_width, reference_height, other_width, other_height}) > 65536)
    throw std::invalid_argument("sphere sweep: images wider or higher than 65536 px");
  std::vector<Eigen::Vector3d> directions(samples_);
  std::vector<BilinearTap> reference_px(samples_);
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      bool seen = true;
      for (int i = 0; i < n && seen; ++i)
        for (int j = 0; j < n && seen; ++j) {
          const int s = i * n + j;
          directions[s] = grid.direction(row + (i + 0.5) / n, col + (j + 0.5) / n);
          Eigen::Vector2d px;
          seen = reference.project(directions[s], px) && inside(px, reference_width, reference_height);
          if (seen) reference_px[s] = bilinearTap(px, reference_width, reference_height);
        }
      if (!seen) continue;
      Tile tile;
      tile.row = row;
      tile.col = col;
      tile.first = reference_px_.size();
      tile.other = other_px_.size();
      tile.usable.assign(options_.hypotheses, 1);
      bool any = false;
      for (int k = 0; k < options_.hypotheses; ++k) {
        const double rho = hypothesis(k);
        for (int s = 0; s < samples_; ++s) {
          Eigen::Vector2d px(0, 0);
          // The point at depth 1/ρ along d, in the other camera, up to its positive scale 1/ρ.
          const bool ok = other.project(R * directions[s] + rho * t, px) && inside(px, other_width, other_height);
          if (!ok) tile.usable[k] = 0;
          other_px_.push_back(ok ? bilinearTap(px, other_width, other_height) : BilinearTap{});
          tile.gather_safe = tile.gather_safe && gatherSafe(other_px_.back(), other_width, other_height);
        }
        any = any || tile.usable[k] != 0;
      }
      if (!any) {
        other_px_.resize(tile.other);
        continue;
      }
      reference_px_.insert(reference_px_.end(), reference_px.begin(), reference_px.end());
      for (const Eigen::Vector3d& d : directions) directions_.push_back(d.cast<float>());
      tiles_.push_back(std::move(tile));
    }
}

double SphereSweep::hypothesis(int k) const {
  return k * (1.0 / options_.min_depth_m) / (options_.hypotheses - 1);
}

std::size_t SphereSweep::tableBytes() const {
  return (reference_px_.size() + other_px_.size()) * sizeof(BilinearTap);
}

bool SphereSweep::fits(const ReferencePatches& patches) const {
  return patches.textured.size() == tiles_.size() && patches.sum_aa.size() == tiles_.size() &&
         patches.a.size() == tiles_.size() * static_cast<std::size_t>(samples_);
}

bool SphereSweep::accepts(const GreyImage& reference, const GreyImage& other) const {
  return reference.pixels && other.pixels && reference.width == reference_width_ && reference.height == reference_height_ &&
         other.width == other_width_ && other.height == other_height_ && reference.width >= 2 && reference.height >= 2 &&
         other.width >= 2 && other.height >= 2 && reference.stride >= reference.width && other.stride >= other.width;
}

SweepResult SphereSweep::estimate(const GreyImage& reference, const GreyImage& other, const std::vector<EarlierView>& earlier) const {
  if (!accepts(reference, other)) return decide({}, {}, {}, {});
  // The buffers stay with the thread: half a megabyte a sweep, freshly mapped and faulted in
  // every time, cost more than the steps' hand-over.
  thread_local ReferencePatches patches;
  thread_local std::vector<float> costs;
  referencePatches(reference, patches);
  pairCosts(patches, other, costs);
  return decide(reference, patches, costs, earlier);
}

SphereSweep::ReferencePatches SphereSweep::referencePatches(const GreyImage& reference) const {
  ReferencePatches patches;
  referencePatches(reference, patches);
  return patches;
}

void SphereSweep::referencePatches(const GreyImage& reference, ReferencePatches& patches) const {
  patches.a.clear();
  patches.sum_aa.clear();
  patches.textured.clear();
  if (!reference.pixels || reference.width != reference_width_ || reference.height != reference_height_ ||
      reference.stride < reference.width)
    return;
  patches.a.resize(tiles_.size() * static_cast<std::size_t>(samples_));
  patches.sum_aa.resize(tiles_.size());
  patches.textured.resize(tiles_.size());
  const float inv_n = 1.0F / static_cast<float>(samples_);
  for (std::size_t t = 0; t < tiles_.size(); ++t) {
    float* a = &patches.a[t * static_cast<std::size_t>(samples_)];
    float sum_a = 0, sum_aa = 0;
    for (int s = 0; s < samples_; ++s) {
      a[s] = tapGrey(reference.pixels, reference.stride, reference_px_[tiles_[t].first + s]);
      sum_a += a[s];
    }
    const float mean_a = sum_a * inv_n;
    for (int s = 0; s < samples_; ++s) {
      a[s] -= mean_a;
      sum_aa += a[s] * a[s];
    }
    patches.sum_aa[t] = sum_aa;
    patches.textured[t] = std::sqrt(sum_aa * inv_n) >= options_.min_texture;
  }
}

std::vector<float> SphereSweep::pairCosts(const ReferencePatches& patches, const GreyImage& other) const {
  std::vector<float> costs;
  pairCosts(patches, other, costs);
  return costs;
}

void SphereSweep::pairCosts(const ReferencePatches& patches, const GreyImage& other, std::vector<float>& costs) const {
  const std::size_t hypotheses = static_cast<std::size_t>(options_.hypotheses);
  costs.assign(tiles_.size() * hypotheses, std::numeric_limits<float>::infinity());
  if (!fits(patches) || !other.pixels || other.width != other_width_ || other.height != other_height_ || other.stride < other.width)
    return;
  const bool simd = options_.simd && gatherOffsetsFit(other.stride, other.height);
  for (std::size_t t = 0; t < tiles_.size(); ++t) {
    if (!patches.textured[t]) continue;
    // Every hypothesis's cost in one call (eight at a step where the CPU can).
    const Tile& tile = tiles_[t];
    patchCosts(other.pixels, other.stride, &other_px_[tile.other], &patches.a[t * static_cast<std::size_t>(samples_)],
               patches.sum_aa[t], samples_, options_.hypotheses, tile.usable.data(), &costs[t * hypotheses],
               simd && tile.gather_safe);
  }
}

SweepResult SphereSweep::decide(const GreyImage& reference, const ReferencePatches& patches, const std::vector<float>& costs,
                                const std::vector<EarlierView>& earlier_views) const {
  SweepResult result;
  result.inverse_depth = render::InverseDepthGrid(options_.tile_deg, 0.0F);
  render::InverseDepthGrid& grid = result.inverse_depth;
  result.confidence.assign(static_cast<std::size_t>(grid.rows()) * grid.cols(), 0.0F);
  result.tiles_seen = static_cast<int>(tiles_.size());
  const std::size_t hypotheses = static_cast<std::size_t>(options_.hypotheses);
  if (!reference.pixels || reference.width != reference_width_ || reference.height != reference_height_ ||
      reference.stride < reference.width || !fits(patches) || costs.size() != tiles_.size() * hypotheses)
    return result;
  std::vector<EarlierView> earlier;
  for (const EarlierView& view : earlier_views)
    if (view.image.pixels && view.image.width == reference_width_ && view.image.height == reference_height_) earlier.push_back(view);
  // The view whose camera centre lies farthest across the optical axis first: the one a matched
  // tile is checked against (the sharpest test).
  const auto across = [](const EarlierView& view) {
    const Eigen::Vector3d c = -view.T_earlier_reference.linear().transpose() * view.T_earlier_reference.translation();
    return std::hypot(c.x(), c.y());
  };
  if (earlier.size() > 1) {
    const auto widest = std::max_element(earlier.begin(), earlier.end(),
                                         [&](const EarlierView& x, const EarlierView& y) { return across(x) < across(y); });
    std::rotate(earlier.begin(), widest, widest + 1);
  }

  std::vector<float> cost(hypotheses);
  std::vector<EarlierView> views;  // a tile's informative ones
  for (std::size_t t = 0; t < tiles_.size(); ++t) {
    if (!patches.textured[t]) continue;
    const Tile& tile = tiles_[t];
    const float* a = &patches.a[t * static_cast<std::size_t>(samples_)];
    const float sum_aa = patches.sum_aa[t];
    // The tile's costs (a hypothesis whose patch leaves the other image has none, whoever computed
    // them), then the first lowest.
    for (std::size_t k = 0; k < hypotheses; ++k)
      cost[k] = tile.usable[k] ? costs[t * hypotheses + k] : std::numeric_limits<float>::infinity();
    int best = -1;
    for (int k = 0; k < options_.hypotheses; ++k)
      if (std::isfinite(cost[k]) && (best < 0 || cost[k] < cost[best])) best = k;
    if (best < 0 || 1.0F - cost[best] < options_.min_correlation) continue;
    float runner_up = std::numeric_limits<float>::infinity();
    for (int k = 0; k < options_.hypotheses; ++k)
      if (std::abs(k - best) > 1) runner_up = std::min(runner_up, cost[k]);
    const std::size_t index = static_cast<std::size_t>(tile.row) * grid.cols() + tile.col;
    const bool ambiguous = runner_up - cost[best] < options_.min_margin;
    if (ambiguous) ++result.tiles_ambiguous;
    // A parabola through the best and its neighbours (where both are usable) places the minimum
    // between hypotheses.
    double rho = hypothesis(best);
    if (best > 0 && best + 1 < options_.hypotheses && std::isfinite(cost[best - 1]) && std::isfinite(cost[best + 1])) {
      const double c0 = cost[best - 1], c1 = cost[best], c2 = cost[best + 1];
      const double curvature = c0 - 2.0 * c1 + c2;
      if (curvature > 1e-9) rho += std::clamp(0.5 * (c0 - c2) / curvature, -0.5, 0.5) * hypothesis(1);
    }
    // The earlier views decide an ambiguous tile, and look again at one whose pair cost has another
    // local minimum within the candidate window where the widest view does not correlate at the
    // pair's best: a pattern's true depth can lose to an alias by far more than the margin where
    // no hypothesis hits its narrow peak, and the pair's gate then passes the alias.
    if (!earlier.empty() && (ambiguous || hasOtherCandidate(cost, best))) {
      bool look_again = ambiguous;
      if (!look_again) {
        // The widest view (first, above) at the pair's depth. Checking every view measured the same
        // on the bench's scenes at 1–2 ms more a pair. A view that does not see the patch there
        // (outside its image) says nothing.
        const float then = projectedCost(tile, a, sum_aa, reference_, earlier[0].T_earlier_reference, rho, earlier[0].image);
        look_again = std::isfinite(then) && 1.0F - then < options_.min_correlation;
      }
      views.clear();
      if (look_again) informativeViews(tile, reference, earlier, views);
      if (!views.empty()) {
        if (const std::optional<Decided> decided = resolveWithEarlier(tile, a, sum_aa, cost, best, views)) {
          grid.at(tile.row, tile.col) = static_cast<float>(std::max(decided->rho, 0.0));
          result.confidence[index] = std::max(decided->confidence, 1e-3F);
          ++result.tiles_decided_by_motion;
          ++result.tiles_matched;
          continue;
        }
      }
    }
    if (ambiguous) continue;  // the views did not decide it either
    grid.at(tile.row, tile.col) = static_cast<float>(std::max(rho, 0.0));
    result.confidence[index] = 1.0F - cost[best];
    ++result.tiles_matched;
  }
  fillAndSmooth(grid, result.confidence);
  return result;
}

bool SphereSweep::isCandidate(const std::vector<float>& cost, int k, int best) const {
  const float limit = cost[best] + static_cast<float>(options_.motion_candidate_window);
  const float left = k > 0 ? cost[k - 1] : std::numeric_limits<float>::infinity();
  const float right = k + 1 < options_.hypotheses ? cost[k + 1] : std::numeric_limits<float>::infinity();
  return cost[k] <= limit && cost[k] <= left && cost[k] < right;  // a local minimum (the last of a tie)
}

bool SphereSweep::hasOtherCandidate(const std::vector<float>& cost, int best) const {
  for (int k = 0; k < options_.hypotheses; ++k)
    if (std::abs(k - best) > 1 && isCandidate(cost, k, best)) return true;
  return false;
}

float SphereSweep::projectedCost(const Tile& tile, const float* a, float sum_aa, const calib::GenericCamera& camera,
                                 const Eigen::Isometry3d& T_view_reference, double rho, const GreyImage& image) const {
  const int n = options_.samples_per_side;
  const Eigen::Vector3f* directions = &directions_[tile.first];
  const bool simd = options_.simd && gatherOffsetsFit(image.stride, image.height);
  if (options_.motion_corner_projection && n >= 3) {
    // The corners, then the sums over the taps between them: every sample is a convex combination
    // of the corners, inside wherever they are.
    PatchCorners corners;
    if (!projectPatchCorners(camera, directions, n, T_view_reference, rho, corners)) return std::numeric_limits<float>::infinity();
    for (const Eigen::Vector2d* corner : {&corners.p00, &corners.p01, &corners.p10, &corners.p11})
      if (!inside(*corner, image.width, image.height)) return std::numeric_limits<float>::infinity();
    return patchCost(patchSumsBetweenCorners(image.pixels, image.stride, image.width, image.height, corners, n, a, simd), sum_aa,
                     samples_);
  }
  thread_local std::vector<Eigen::Vector2d> px;
  thread_local std::vector<BilinearTap> taps;
  px.resize(samples_);
  taps.resize(samples_);
  if (!projectPatch(camera, directions, n, T_view_reference, rho, false, px.data())) return std::numeric_limits<float>::infinity();
  for (int s = 0; s < samples_; ++s)
    if (!inside(px[s], image.width, image.height)) return std::numeric_limits<float>::infinity();
  for (int s = 0; s < samples_; ++s) taps[s] = bilinearTap(px[s], image.width, image.height);
  const bool gather_safe = std::all_of(taps.begin(), taps.end(), [&](const BilinearTap& t) { return gatherSafe(t, image.width, image.height); });
  return patchCost(patchSums(image.pixels, image.stride, taps.data(), a, samples_, simd && gather_safe), sum_aa, samples_);
}

void SphereSweep::informativeViews(const Tile& tile, const GreyImage& reference, const std::vector<EarlierView>& earlier,
                                   std::vector<EarlierView>& informative) const {
  // Only the views that see the patch's texture move: a motion along stripes sees every candidate
  // alike, and what differs between its costs then is the resampling, which favours no parallax
  // at all. The patch's grey gradients (at each sample, across its pixel block) against the direction
  // in which the view's parallax moves the tile in the reference image (toward the view's centre).
  thread_local std::vector<Eigen::Vector2d> gradients;
  gradients.resize(samples_);
  double energy = 0;
  for (int s = 0; s < samples_; ++s) {
    // The grey gradient across the tap's own 2 × 2 block, weighted as its bilinear sample is.
    const BilinearTap& t = reference_px_[tile.first + s];
    const std::uint8_t* p = reference.pixels + static_cast<std::ptrdiff_t>(t.y) * reference.stride + t.x;
    const double wx = t.wx / 256.0, wy = t.wy / 256.0;
    const int stride = reference.stride;
    gradients[s] = Eigen::Vector2d((1.0 - wy) * (p[1] - p[0]) + wy * (p[stride + 1] - p[stride]),
                                   (1.0 - wx) * (p[stride] - p[0]) + wx * (p[stride + 1] - p[1]));
    energy += gradients[s].squaredNorm();
  }
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int s = 0; s < samples_; ++s) centre += directions_[tile.first + s].cast<double>();
  centre.normalize();
  Eigen::Vector2d centre_px;
  if (energy <= 0.0 || !reference_.project(centre, centre_px)) return;
  for (const EarlierView& view : earlier) {
    const Eigen::Vector3d c = -view.T_earlier_reference.linear().transpose() * view.T_earlier_reference.translation();
    const Eigen::Vector3d across = c - c.dot(centre) * centre;  // the view's centre, seen across the tile's ray
    Eigen::Vector2d moved_px;
    if (across.norm() < 1e-9 || !reference_.project(centre + 0.01 * across.normalized(), moved_px)) continue;
    const Eigen::Vector2d e = (moved_px - centre_px).normalized();
    double along = 0;
    for (const Eigen::Vector2d& g : gradients) along += g.dot(e) * g.dot(e);
    if (along >= options_.motion_min_gradient_fraction * energy) informative.push_back(view);
  }
}

std::optional<SphereSweep::Decided> SphereSweep::resolveWithEarlier(const Tile& tile, const float* a, float sum_aa,
                                                                    const std::vector<float>& cost, int best,
                                                                    const std::vector<EarlierView>& earlier) const {
  if (earlier.empty()) return std::nullopt;
  // The candidates: the pair's local minima within the window, each where the pair's parabola puts
  // it between hypotheses.
  const double step = hypothesis(1);
  thread_local std::vector<double> candidates;
  candidates.clear();
  for (int k = 0; k < options_.hypotheses; ++k) {
    if (!isCandidate(cost, k, best)) continue;
    double rho = hypothesis(k);
    if (k > 0 && k + 1 < options_.hypotheses && std::isfinite(cost[k - 1]) && std::isfinite(cost[k + 1]) &&
        cost[k - 1] - 2.0 * cost[k] + cost[k + 1] > 1e-9)
      rho += std::clamp(0.5 * (cost[k - 1] - cost[k + 1]) / (cost[k - 1] - 2.0 * cost[k] + cost[k + 1]), -0.5, 0.5) * step;
    candidates.push_back(rho);
  }
  // Each view's cost at every candidate. A view that does not see the patch at every candidate
  // (outside its image at some depth, most often the nearest) takes no part: comparing the rest
  // without the missing ones could pass an alias over the truth.
  thread_local std::vector<float> sum, worst, view_cost;
  sum.assign(candidates.size(), 0.0F);
  worst.assign(candidates.size(), 0.0F);
  view_cost.resize(candidates.size());
  int views = 0;
  for (const EarlierView& view : earlier) {
    bool sees_all = true;
    for (std::size_t c = 0; c < candidates.size() && sees_all; ++c) {
      view_cost[c] = projectedCost(tile, a, sum_aa, reference_, view.T_earlier_reference, candidates[c], view.image);
      sees_all = std::isfinite(view_cost[c]);
    }
    if (!sees_all) continue;
    ++views;
    bool any_correlates = false;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      sum[c] += view_cost[c];
      worst[c] = std::max(worst[c], view_cost[c]);
      any_correlates = any_correlates || !(1.0F - worst[c] < options_.min_correlation);
    }
    // Whichever candidate the sums choose must correlate in every view (below), and a candidate's
    // worst view only gets worse: where none correlates in every view so far, none will (a fifth
    // of the stripes' tiles at the first view, its second view then spared).
    if (!any_correlates) return std::nullopt;
  }
  if (views == 0 || candidates.empty()) return std::nullopt;
  const std::size_t chosen = static_cast<std::size_t>(std::min_element(sum.begin(), sum.end()) - sum.begin());
  // Each view must correlate there on its own (a scene that moved between the captures does not),
  // and every other candidate must be worse by the margin in the views' summed cost (a view whose
  // own aliases fall on the pair's decides nothing).
  if (1.0F - worst[chosen] < options_.min_correlation) return std::nullopt;
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (c != chosen && std::abs(candidates[c] - candidates[chosen]) > 1.5 * step && sum[c] - sum[chosen] < options_.min_margin)
      return std::nullopt;
  return Decided{candidates[chosen], 1.0F - sum[chosen] / static_cast<float>(views)};
}

}  // namespace telesphere::xr::depth
