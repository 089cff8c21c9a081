// SPDX-License-Identifier: MIT
/// @brief Double Sphere camera model (Usenko, Demmel, Cremers, 3DV 2018): the model of the paper's
///        >180° fisheye lenses. Parameters [fx, fy, cx, cy, xi, alpha], model name "ds".
///
/// Projection of a point p = (x, y, z) in the camera's optical frame (x right, y down, z forward):
///   d1 = |p|,  k = xi·d1 + z,  d2 = sqrt(x² + y² + k²),  den = alpha·d2 + (1 − alpha)·k,
///   u = fx·x/den + cx,  v = fy·y/den + cy.
/// A point projects iff z > −w2·d1 with
///   w1 = alpha/(1 − alpha) for alpha ≤ 0.5, (1 − alpha)/alpha otherwise,
///   w2 = (w1 + xi)/sqrt(2·w1·xi + xi² + 1),
/// i.e. iff its angle θ from the optical axis is below maxAngle() = acos(−w2). This is what lets
/// the model represent fields of view beyond 180° (θ > 90°). For xi < 0 or xi > 1 the image
/// radius can peak (the image folds back) or den reach 0 before that bound; validity then ends
/// there instead (found once per camera), so that valid pixels and valid rays correspond one to
/// one. (Usenko's bound holds for xi ∈ [0, 1]; the property tests check all three ranges.)
///
/// Unprojection (closed form): with mx = (u − cx)/fx, my = (v − cy)/fy, r² = mx² + my²,
///   valid iff alpha ≤ 0.5 or r² < 1/(2·alpha − 1), and mz² + (1 − xi²)·r² ≥ 0 where
///   mz = (1 − alpha²·r²)/(alpha·sqrt(1 − (2·alpha − 1)·r²) + 1 − alpha),
///   d = (mx·k, my·k, mz·k − xi) with k = (mz·xi + sqrt(mz² + (1 − xi²)·r²))/(mz² + r²),
/// and the result must itself satisfy the projection condition (so both directions agree on the
/// valid set). d is a unit vector up to rounding.
///
/// Parameter domain: fx, fy > 0; cx, cy finite; alpha ∈ [0, 1]; xi ∈ (−1, 1e3]. Tested over
/// that domain (tests/calib/test_camera_models.cpp); alpha = 0 and xi = 0 is the pinhole camera.
///
/// Templated on Scalar so that double (reference, calibration), float (parity with the GLSL) and
/// ceres::Jet (autodiff) share this one implementation. No NaN leaves the model: an invalid
/// input (NaN, inf, the camera centre, a direction outside the valid cone) returns false and zero
/// outputs.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "calib/camera_model_support.h"
#include "calib/debug_assert.h"
#include "calib/scalar_math.h"

namespace telesphere::calib {

template <typename Scalar_>
class DoubleSphereCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 6;
  static constexpr std::string_view kName = "ds";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {"fx", "fy", "cx",
                                                                           "cy", "xi", "alpha"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat2x3 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2xP = Eigen::Matrix<Scalar, 2, kNumParams>;

  /// A camera with the given parameters [fx, fy, cx, cy, xi, alpha] (checked in debug builds;
  /// use checkParams() to validate user input first).
  explicit DoubleSphereCamera(const Params& params) : params_(params) {
    TS_ASSERT(!checkParams(valuesOf(params_)), *checkParams(valuesOf(params_)));
    const Scalar& xi = params_[4];
    const Scalar& alpha = params_[5];
    using std::sqrt;
    const Scalar w1 = alpha > Scalar(0.5) ? (Scalar(1) - alpha) / alpha : alpha / (Scalar(1) - alpha);
    w2_ = (w1 + xi) / sqrt(Scalar(2) * w1 * xi + xi * xi + Scalar(1));
    // For xi outside [0, 1] the image radius can peak (fold back) or run off to infinity
    // (den → 0) before the w2 bound; validity then ends there, so that every valid pixel has
    // exactly one ray. Inside [0, 1] the w2 bound is exact (Usenko et al.), and Jets built there
    // by calibration pay nothing for the scan.
    const double xi_value = scalarValue(xi);
    if (xi_value < 0.0 || xi_value > 1.0) {
      const double limit = std::acos(-scalarValue(w2_));
      const double fold = foldAngle(xi_value, scalarValue(alpha), limit);
      if (fold < limit) w2_ = Scalar(-std::cos(fold));
    }
  }

  const Params& params() const { return params_; }

  /// Why the parameters are outside the model's domain (naming the parameter), or nothing.
  static std::optional<std::string> checkParams(const Eigen::Matrix<double, kNumParams, 1>& p) {
    return firstError({checkPositive("fx", p[0]), checkPositive("fy", p[1]),
                       checkFinite("cx", p[2]), checkFinite("cy", p[3]),
                       checkOpenClosed("xi", p[4], -1.0, 1e3), checkClosed("alpha", p[5], 0.0, 1.0)});
  }

  /// Largest angle (rad) from the optical axis that the model represents: a direction projects
  /// iff its angle θ < maxAngle() = acos(−w2). π/2 is a 180° field of view; the lens in the image
  /// may cover less (see cameraFieldOfView in calib/camera_field_of_view.h).
  Scalar maxAngle() const {
    using std::acos;
    return acos(-w2_);
  }

  /// Projects p_cam (metres, camera optical frame) to out_px (pixels, origin at the centre of the
  /// top-left pixel). Optional Jacobians d_px_d_p (2×3) and d_px_d_params (2×6).
  /// Returns false (outputs zeroed) for the camera centre, NaN/inf, or θ ≥ maxAngle().
  template <typename Derived>
  bool project(const Eigen::MatrixBase<Derived>& p_cam, Vec2& out_px, Mat2x3* d_px_d_p = nullptr,
               Mat2xP* d_px_d_params = nullptr) const {
    const Scalar d1_2 = p_cam[0] * p_cam[0] + p_cam[1] * p_cam[1] + p_cam[2] * p_cam[2];
    if (squaredNormInSafeRange(d1_2)) [[likely]] {
      return projectSafe(p_cam[0], p_cam[1], p_cam[2], d1_2, out_px, d_px_d_p, d_px_d_params);
    }
    return projectRescaled(*this, p_cam, out_px, d_px_d_p, d_px_d_params);
  }

  /// Unprojects out_d_cam (unit bearing in the camera optical frame) from px (pixels).
  /// Returns false (output zeroed) outside the model's image region or for NaN/inf.
  template <typename Derived>
  bool unproject(const Eigen::MatrixBase<Derived>& px, Vec3& out_d_cam) const {
    using std::sqrt;
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& xi = params_[4];
    const Scalar& alpha = params_[5];

    const Scalar mx = (px[0] - cx) * inv_fx_;
    const Scalar my = (px[1] - cy) * inv_fy_;
    const Scalar r2 = mx * mx + my * my;
    const Scalar two_alpha_m1 = Scalar(2) * alpha - Scalar(1);
    // Outside the image circle of alpha > 0.5 (and NaN/inf) the model has no ray.
    if (!(isFiniteScalar(r2) && two_alpha_m1 * r2 < Scalar(1))) return invalidUnproject(out_d_cam);

    const Scalar mz = (Scalar(1) - alpha * alpha * r2) /
                      (alpha * sqrt(Scalar(1) - two_alpha_m1 * r2) + Scalar(1) - alpha);
    const Scalar mz2 = mz * mz;
    const Scalar disc = mz2 + (Scalar(1) - xi * xi) * r2;
    if (!(disc >= Scalar(0))) return invalidUnproject(out_d_cam);
    const Scalar k = (mz * xi + sqrt(disc)) / (mz2 + r2);
    out_d_cam << k * mx, k * my, k * mz - xi;
    if (!(out_d_cam[2] > -w2_ && isFiniteScalar(out_d_cam[2]))) return invalidUnproject(out_d_cam);
    return true;
  }

  /// The same camera in another scalar type (double → float for GLSL parity, → Jet for autodiff).
  template <typename Other>
  DoubleSphereCamera<Other> cast() const {
    return DoubleSphereCamera<Other>(params_.template cast<Other>());
  }

 private:
  /// First angle in (0, limit) where the image radius sin θ/den(θ) of a unit ray stops rising or
  /// den(θ) reaches 0, or limit when neither happens.
  static double foldAngle(double xi, double alpha, double limit) {
    // For a unit ray at angle t: k = xi + cos t, d2 = sqrt(1 + 2·xi·cos t + xi²),
    // den = alpha·d2 + (1 − alpha)·k, radius = sin t/den, and
    // d radius/dt · den² = cos t·den + sin² t·(alpha·xi/d2 + 1 − alpha).
    const auto good = [&](double t) {
      const double c = std::cos(t), s2 = 1.0 - c * c;
      const double d2 = std::sqrt(std::max(0.0, 1.0 + 2.0 * xi * c + xi * xi));
      const double den = alpha * d2 + (1.0 - alpha) * (xi + c);
      return den > 0.0 && c * den + s2 * (alpha * xi / d2 + 1.0 - alpha) > 0.0;
    };
    // xi > 1: the first sphere's closed-form inverse holds only for cos t > −1/xi.
    if (xi > 1.0) limit = std::min(limit, std::acos(-1.0 / xi));
    constexpr int kSteps = 512;
    double prev = 0.0;
    for (int i = 1; i <= kSteps; ++i) {
      const double t = i < kSteps ? limit * i / kSteps : limit * (1.0 - 1e-12);
      if (good(t)) {
        prev = t;
        continue;
      }
      double lo = prev, hi = t;  // good(lo), !good(hi)
      for (int it = 0; it < 100 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        (good(mid) ? lo : hi) = mid;
      }
      return lo;
    }
    return limit;
  }

  bool projectSafe(const Scalar& x, const Scalar& y, const Scalar& z, const Scalar& d1_2,
                   Vec2& out_px, Mat2x3* d_px_d_p, Mat2xP* d_px_d_params) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& xi = params_[4];
    const Scalar& alpha = params_[5];

    const Scalar d1 = sqrt(d1_2);
    // Written as !(a > b) so that NaN lands on the invalid side.
    if (!(z > -w2_ * d1)) return invalidProject(out_px, d_px_d_p, d_px_d_params);
    const Scalar r2 = x * x + y * y;
    const Scalar k = xi * d1 + z;
    const Scalar d2 = sqrt(r2 + k * k);
    const Scalar den = alpha * d2 + (Scalar(1) - alpha) * k;
    if (!(den > Scalar(0))) return invalidProject(out_px, d_px_d_p, d_px_d_params);

    const Scalar inv_den = Scalar(1) / den;
    const Scalar mx = x * inv_den;
    const Scalar my = y * inv_den;
    out_px << fx * mx + cx, fy * my + cy;

    if (d_px_d_p || d_px_d_params) {
      const Scalar c = xi / d1;
      // ∂den/∂x = x·f_xy, ∂den/∂y = y·f_xy, ∂den/∂z = f_z.
      const Scalar f_xy = alpha * (Scalar(1) + k * c) / d2 + (Scalar(1) - alpha) * c;
      const Scalar g = alpha * k / d2 + Scalar(1) - alpha;
      const Scalar f_z = (c * z + Scalar(1)) * g;
      if (d_px_d_p) {
        auto& J = *d_px_d_p;
        J(0, 0) = fx * inv_den * (Scalar(1) - mx * x * f_xy);
        J(0, 1) = -fx * inv_den * mx * y * f_xy;
        J(0, 2) = -fx * inv_den * mx * f_z;
        J(1, 0) = -fy * inv_den * my * x * f_xy;
        J(1, 1) = fy * inv_den * (Scalar(1) - my * y * f_xy);
        J(1, 2) = -fy * inv_den * my * f_z;
      }
      if (d_px_d_params) {
        auto& J = *d_px_d_params;
        J.setZero();
        J(0, 0) = mx;
        J(0, 2) = Scalar(1);
        J(1, 1) = my;
        J(1, 3) = Scalar(1);
        const Scalar dden_dxi = d1 * g;
        const Scalar dden_dalpha = d2 - k;
        J(0, 4) = -fx * mx * dden_dxi * inv_den;
        J(1, 4) = -fy * my * dden_dxi * inv_den;
        J(0, 5) = -fx * mx * dden_dalpha * inv_den;
        J(1, 5) = -fy * my * dden_dalpha * inv_den;
      }
    }
    return true;
  }

  Params params_;
  Scalar w2_{};
  Scalar inv_fx_ = Scalar(1) / params_[0];  // unprojection multiplies instead of dividing
  Scalar inv_fy_ = Scalar(1) / params_[1];
};

}  // namespace telesphere::calib
