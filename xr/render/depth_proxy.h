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
/// Fixed-point steps the renderer (GPU and reference) takes per eye ray on a grid proxy.
constexpr int kGridProxySteps = 3;
/// Where the four tiles around a direction differ in inverse depth by more than this times the
/// tile size, the grid proxy takes the nearest of them instead of interpolating: a depth edge.
/// Bilinear there puts the edge of a near object at a depth between it and its background, so
/// the object's outline moves while the head moves. The nearest tile keeps the outline on the
/// object and moves the background up to one tile beside it instead. Below it (noise, slanted
/// surfaces, whose spread grows with the tile) the grid interpolates. For 4° tiles it is a jump of
/// 0.3 1/m, about 1° of parallax at a 6 cm head offset. Measured both ways (bilinear, half, this,
/// twice) by `telesphere-bench depth`.
constexpr double kGridEdgeSlopePerMPerDeg = 0.075;

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
  /// `edge_jump_per_m` the largest of them (the nearest); infinity: sample(). What the grid proxy
  /// meets (gridProxyHit) and the shader's proxyRadius compute.
  double sampleNearestAtEdges(const Eigen::Vector3d& d, double edge_jump_per_m) const;

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

/// The point (camera frame) an eye ray shows under the grid proxy: on the surface
/// |p| = 1/grid(p/|p|) along o + t·d (o the eye in the camera frame, d unit). `steps`
/// fixed-point steps from the sphere at the grid's radius toward d: r_{k+1} = 1/grid(p_k),
/// p_k = o + t(r_k)·d with t the far root of |o + t·d| = r_k (sphereFarHit). Converges while the
/// eye is nearer the camera than the surface by a margin (|o| ≪ r); at a depth edge it lands on
/// one side or the other (where no proxy can be right). The grid is read with
/// sampleNearestAtEdges(·, edge_slope_per_m_per_deg × the tile size); infinity: bilinear. Nothing
/// only where a sphere is missed, which cannot happen while |o| < kMinProxyRadiusM.
std::optional<Eigen::Vector3d> gridProxyHit(const InverseDepthGrid& grid, const Eigen::Vector3d& o,
                                            const Eigen::Vector3d& d, int steps,
                                            double edge_slope_per_m_per_deg = kGridEdgeSlopePerMPerDeg);

/// The point (camera frame) an eye ray shows under a sphere of radius r (the fixed and the
/// single-radius proxies); nothing where the ray misses it.
std::optional<Eigen::Vector3d> sphereProxyHit(double radius_m, const Eigen::Vector3d& o, const Eigen::Vector3d& d);

}  // namespace telesphere::xr::render
