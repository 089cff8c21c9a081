// SPDX-License-Identifier: MIT
/// @brief What the renderer assumes about the scene's depth (DESIGN.md §11, #35), in double
///        precision: the fixed sphere, one radius from a centre-weighted median of inverse depth,
///        and a coarse inverse-depth grid around each camera that every eye ray meets in a few
///        steps. The CPU reference of the proxies and what `telesphere-bench depth` measures;
///        proxies work in inverse depth because the error they leave, γ ≈ Δx·(1/r − 1/d), is
///        linear in it.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::xr::render {

/// Radii the proxies keep to (m): nearer than kMinProxyRadiusM would put the proxy inside the lens
/// housing (and a point at the camera centre has no direction); beyond kMaxProxyRadiusM (inverse
/// depth 0: the sky, a far wall) every radius shows the same picture to a fraction of a pixel.
constexpr double kMinProxyRadiusM = 0.1;
constexpr double kMaxProxyRadiusM = 1000.0;
/// Refinement steps the renderer (GPU and reference) takes per eye ray on a grid proxy, once its
/// march has bracketed the first crossing (bisections; without the march, fixed-point steps).
constexpr int kGridProxySteps = 3;
/// The grid proxy's march along each eye ray (gridProxyHit): a step moves the ray's point, as the
/// camera sees it, by about this many tiles (|o × d| · Δρ radians, which is low by 1/cos of the
/// angle between the point and the ray: 4 % at 16°), so a ray seldom steps over a tile it passes;
/// it can over a tile's corner it clips (2.4 % of the rays at a box's outline in the unit test),
/// and beyond kGridMarchMaxSteps the steps grow. Fewer steps start the refinement from a wider
/// bracket, more cost a lookup each. Infinity: no march,
/// the fixed-point steps from the ray's own direction (before the march: they settle on the
/// background where the ray's own direction lies beyond a near object's edge, though the ray
/// crosses the object's tiles first). Measured both ways by `telesphere-bench depth`.
constexpr double kGridMarchStepTiles = 0.5;
/// The most march steps one eye ray takes (the shader's loop bound): an eye 10 cm from the camera
/// and a tile at the nearest radius take 2 × 0.1 m × 10 1/m / 4° ≈ 29 at 4° tiles.
constexpr int kGridMarchMaxSteps = 64;
/// Where the four tiles around a direction differ in inverse depth by more than this times the
/// tile size, the grid proxy takes one of them instead of interpolating: a depth edge (GridEdgeTile
/// says which). Bilinear there puts the edge of a near object at a depth between it and its
/// background, so the object's outline moves while the head moves. Below it (noise, slanted
/// surfaces, whose spread grows with the tile) the grid interpolates. For 4° tiles it is a jump of
/// 0.3 1/m, about 1° of parallax at a 6 cm head offset. Measured both ways (bilinear, half, this,
/// twice) by `telesphere-bench depth`.
constexpr double kGridEdgeSlopePerMPerDeg = 0.075;

/// Which of the four tiles around a direction the grid proxy takes at a depth edge.
enum class GridEdgeTile {
  /// The tile whose centre is closest (the renderer's): a near object's outline on the line
  /// halfway between its last tile's centre and its background's, where a tile's majority put it.
  kClosest,
  /// The largest inverse depth of the four (the nearest surface): a near object widened by up to
  /// a tile. Right for fixed-point steps from the ray's own direction, which then keep the
  /// object's outline on the side they start from; the march meets the widened object first and
  /// shows a strip of background beside it. CPU only, for `telesphere-bench depth`'s comparison.
  kNearestDepth,
};

/// 1/inverse_depth clamped to [kMinProxyRadiusM, kMaxProxyRadiusM]; NaN or negative → the far bound.
double radiusFromInverseDepth(double inverse_depth_per_m);

/// A coarse inverse-depth map (1/m) around one camera, over every direction (a lens wider than
/// 180° included): tiles of `tile_deg` in longitude λ = atan2(x, z) ∈ (−180°, 180°] (about the
/// camera's y axis, 0 along the optical axis +z) and latitude φ = asin(−y) ∈ [−90°, 90°] (positive
/// up: the camera's y points down). A value is the tile's inverse depth at its centre; between
/// centres it is interpolated bilinearly, longitude wrapping round, latitude clamped at the poles.
class InverseDepthGrid {
 public:
  /// `tile_deg` in (0, 90], dividing 180 (1, 2, 3, 4, 5, 6, 9, 10, …); every tile starts at `inverse_depth`.
  explicit InverseDepthGrid(double tile_deg, float inverse_depth_per_m = 1.0F);

  int rows() const { return rows_; }  ///< latitude bands, from the bottom (φ = −90°) up
  int cols() const { return cols_; }  ///< longitude sectors, from λ = −180°
  double tileDeg() const { return tile_deg_; }

  float& at(int row, int col) { return values_[static_cast<std::size_t>(row) * cols_ + col]; }
  /// All values, row after row from the bottom (what a texture of cols × rows takes as it is).
  const float* data() const { return values_.data(); }
  float at(int row, int col) const { return values_[static_cast<std::size_t>(row) * cols_ + col]; }

  /// Unit direction (camera frame) of a point of the grid in tile units: (row + 0.5, col + 0.5) is
  /// a tile's centre.
  Eigen::Vector3d direction(double row, double col) const;
  /// Unit direction of tile (row, col)'s centre.
  Eigen::Vector3d tileCentre(int row, int col) const { return direction(row + 0.5, col + 0.5); }

  /// Inverse depth (1/m) toward direction `d` (camera frame, any length > 0), interpolated
  /// bilinearly.
  double sample(const Eigen::Vector3d& d) const;
  /// As sample(), but where the four tiles it interpolates between span more than
  /// `edge_jump_per_m` one of them, as `tile` says; infinity: sample(). What the grid proxy meets
  /// (gridProxyHit) and the shader's proxyRadius compute.
  double sampleKeepingEdges(const Eigen::Vector3d& d, double edge_jump_per_m,
                            GridEdgeTile tile = GridEdgeTile::kClosest) const;

 private:
  double tile_deg_;
  int rows_, cols_;
  std::vector<float> values_;
};

/// The radius of the single-radius proxy: 1 / the weighted median of the grid's inverse depths,
/// each tile weighted by its solid angle and exp(−θ²/2σ²), θ its angle to `centre` (the gaze, or
/// the view's centre without eye tracking; camera frame). A median, not a mean: a near object in
/// the fovea wins when it covers half the weight, a few wild tiles do not move it.
double centreWeightedRadius(const InverseDepthGrid& grid, const Eigen::Vector3d& centre, double sigma_rad);

/// What an eye ray needs besides the grid to meet it, computed once per grid (O(tiles); the
/// renderer's uniforms).
struct GridProxyParams {
  /// sampleKeepingEdges above this jump (1/m), taking `edge_tile`; infinity: bilinear everywhere.
  double edge_jump_per_m = 0;
  GridEdgeTile edge_tile = GridEdgeTile::kClosest;
  /// Inverse depths the march runs over (1/m): from the grid's largest value (bounded to
  /// 1/kMinProxyRadiusM) down to 1/kMaxProxyRadiusM.
  double inverse_depth_top_per_m = 0, inverse_depth_bottom_per_m = 0;
  /// The angle (rad) the ray's point may move per march step as the camera sees it; infinity: no
  /// march (fixed-point steps from the ray's own direction).
  double march_step_rad = 0;
  int refine_steps = kGridProxySteps;
};

/// The parameters of `grid`'s proxy: one tile at edges (edge_tile, the closest) above `edge_slope_per_m_per_deg` × the
/// tile size (infinity: bilinear), march steps of `march_step_tiles` tiles (infinity: none).
GridProxyParams gridProxyParams(const InverseDepthGrid& grid, double edge_slope_per_m_per_deg = kGridEdgeSlopePerMPerDeg,
                                double march_step_tiles = kGridMarchStepTiles, int refine_steps = kGridProxySteps);

/// How many march steps the ray from o along unit d takes: the angle its point sweeps as the camera
/// sees it, |o × d| · (top − bottom) radians, over the step; at least 1, at most kGridMarchMaxSteps.
int gridMarchSteps(const GridProxyParams& params, const Eigen::Vector3d& o, const Eigen::Vector3d& d);

/// The point (camera frame) an eye ray shows under the grid proxy: where the ray o + t·d (o the eye
/// in the camera frame, d unit) first meets the surface |p| = 1/grid(p/|p|) (the grid read with
/// sampleKeepingEdges, its values bounded to the proxy radii). The ray is followed in the inverse
/// depth ρ of its point p(ρ), the far root of |o + t·d| = 1/ρ, from the top of the grid's values
/// down (outward from the eye), gridMarchSteps steps; the first step where grid(p(ρ)) ≥ ρ (the
/// point at or behind the surface) brackets the crossing, `refine_steps` bisections narrow it, and
/// the point is where the grid minus ρ, linear between the bracket's ends, is 0. At a depth edge the crossing is the object's outline, wherever the ray's
/// own direction lies. Without the march (params.march_step_rad infinite) `refine_steps` fixed-point
/// steps from the sphere at the grid's radius toward d: r_{k+1} = 1/grid(p_k), which settle on
/// whichever surface lies nearest the ray's own direction. Nothing where the ray passes outside the
/// surface (an eye outside it looking away), as for a sphere (sphereProxyHit). The ray is followed
/// from where it comes nearest the camera, so what lies between the eye and that point is not
/// looked at: nothing while the eye is nearer the camera than kMinProxyRadiusM. `lookups`, when
/// given, counts the grid reads.
std::optional<Eigen::Vector3d> gridProxyHit(const InverseDepthGrid& grid, const GridProxyParams& params,
                                            const Eigen::Vector3d& o, const Eigen::Vector3d& d, int* lookups = nullptr);

/// The point (camera frame) an eye ray shows under a sphere of radius r (the fixed and the
/// single-radius proxies); nothing where the ray misses it.
std::optional<Eigen::Vector3d> sphereProxyHit(double radius_m, const Eigen::Vector3d& o, const Eigen::Vector3d& d);

}  // namespace telesphere::xr::render
