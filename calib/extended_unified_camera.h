// SPDX-License-Identifier: MIT
/// @brief Extended Unified Camera Model, EUCM (Khomutenko, Garcia, Martinet, RA-L 2016).
///        Parameters [fx, fy, cx, cy, alpha, beta], model name "eucm".
///
/// Projection of p = (x, y, z) in the optical frame (x right, y down, z forward):
///   rho = sqrt(beta·(x² + y²) + z²),  den = alpha·rho + (1 − alpha)·z,
///   u = fx·x/den + cx,  v = fy·y/den + cy.
/// A point projects iff z > −w·rho with w = alpha/(1 − alpha) for alpha ≤ 0.5 and
/// (1 − alpha)/alpha otherwise; on the unit sphere that is θ < maxAngle() =
/// π − atan2(sqrt(1 − w²), w·sqrt(beta)).
///
/// Unprojection: mx, my, r² as usual; valid iff alpha ≤ 0.5 or r² < 1/(beta·(2·alpha − 1));
///   mz = (1 − beta·alpha²·r²)/(alpha·sqrt(1 − (2·alpha − 1)·beta·r²) + 1 − alpha),
///   d = (mx, my, mz)/|(mx, my, mz)|, and d must satisfy the projection condition.
///
/// Parameter domain: fx, fy > 0; cx, cy finite; alpha ∈ [0, 1]; beta ∈ (0, 1e3].
/// alpha = 0 is the pinhole camera; beta = 1 is the Unified Camera Model.
#pragma once

#include <Eigen/Core>
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
class ExtendedUnifiedCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 6;
  static constexpr std::string_view kName = "eucm";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {"fx", "fy", "cx",
                                                                           "cy", "alpha", "beta"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat2x3 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2xP = Eigen::Matrix<Scalar, 2, kNumParams>;

  explicit ExtendedUnifiedCamera(const Params& params) : params_(params) {
    TS_ASSERT(!checkParams(valuesOf(params_)), *checkParams(valuesOf(params_)));
    const Scalar& alpha = params_[4];
    w_ = alpha > Scalar(0.5) ? (Scalar(1) - alpha) / alpha : alpha / (Scalar(1) - alpha);
  }

  const Params& params() const { return params_; }

  static std::optional<std::string> checkParams(const Eigen::Matrix<double, kNumParams, 1>& p) {
    return firstError({checkPositive("fx", p[0]), checkPositive("fy", p[1]),
                       checkFinite("cx", p[2]), checkFinite("cy", p[3]),
                       checkClosed("alpha", p[4], 0.0, 1.0),
                       checkOpenClosed("beta", p[5], 0.0, 1e3)});
  }

  /// Largest angle (rad) from the optical axis that projects: θ < maxAngle().
  Scalar maxAngle() const {
    using std::atan2;
    using std::sqrt;
    const Scalar pi(3.14159265358979323846);
    return pi - atan2(sqrt(Scalar(1) - w_ * w_), w_ * sqrt(params_[5]));
  }

  /// Projects p_cam (camera optical frame) to out_px; optional Jacobians (2×3, 2×6).
  template <typename Derived>
  bool project(const Eigen::MatrixBase<Derived>& p_cam, Vec2& out_px, Mat2x3* d_px_d_p = nullptr,
               Mat2xP* d_px_d_params = nullptr) const {
    const Scalar n2 = p_cam[0] * p_cam[0] + p_cam[1] * p_cam[1] + p_cam[2] * p_cam[2];
    if (!squaredNormInSafeRange(n2)) [[unlikely]]
      return projectRescaled(*this, p_cam, out_px, d_px_d_p, d_px_d_params);

    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& alpha = params_[4];
    const Scalar& beta = params_[5];
    const Scalar& x = p_cam[0];
    const Scalar& y = p_cam[1];
    const Scalar& z = p_cam[2];

    const Scalar r2 = x * x + y * y;
    const Scalar rho = sqrt(beta * r2 + z * z);
    if (!(z > -w_ * rho)) return invalidProject(out_px, d_px_d_p, d_px_d_params);
    const Scalar den = alpha * rho + (Scalar(1) - alpha) * z;
    if (!(den > Scalar(0))) return invalidProject(out_px, d_px_d_p, d_px_d_params);

    const Scalar inv_den = Scalar(1) / den;
    const Scalar mx = x * inv_den;
    const Scalar my = y * inv_den;
    out_px << fx * mx + cx, fy * my + cy;

    if (d_px_d_p) {
      // ∂den/∂x = x·f_xy, ∂den/∂y = y·f_xy, ∂den/∂z = f_z.
      const Scalar f_xy = alpha * beta / rho;
      const Scalar f_z = alpha * z / rho + Scalar(1) - alpha;
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
      const Scalar dden_dalpha = rho - z;
      const Scalar dden_dbeta = alpha * r2 / (Scalar(2) * rho);
      J(0, 4) = -fx * mx * dden_dalpha * inv_den;
      J(1, 4) = -fy * my * dden_dalpha * inv_den;
      J(0, 5) = -fx * mx * dden_dbeta * inv_den;
      J(1, 5) = -fy * my * dden_dbeta * inv_den;
    }
    return true;
  }

  /// Unprojects px to a unit bearing out_d_cam (camera optical frame).
  template <typename Derived>
  bool unproject(const Eigen::MatrixBase<Derived>& px, Vec3& out_d_cam) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& alpha = params_[4];
    const Scalar& beta = params_[5];

    const Scalar mx = (px[0] - cx) / fx;
    const Scalar my = (px[1] - cy) / fy;
    const Scalar r2 = mx * mx + my * my;
    const Scalar c = (Scalar(2) * alpha - Scalar(1)) * beta;
    if (!(isFiniteScalar(r2) && c * r2 < Scalar(1))) return invalidUnproject(out_d_cam);
    const Scalar mz = (Scalar(1) - beta * alpha * alpha * r2) /
                      (alpha * sqrt(Scalar(1) - c * r2) + Scalar(1) - alpha);
    const Scalar inv_norm = Scalar(1) / sqrt(r2 + mz * mz);
    out_d_cam << mx * inv_norm, my * inv_norm, mz * inv_norm;
    // The projection condition z > −w·rho on the unit bearing.
    const Scalar rho = sqrt(beta * (out_d_cam[0] * out_d_cam[0] + out_d_cam[1] * out_d_cam[1]) +
                            out_d_cam[2] * out_d_cam[2]);
    if (!(out_d_cam[2] > -w_ * rho && isFiniteScalar(out_d_cam[2])))
      return invalidUnproject(out_d_cam);
    return true;
  }

  template <typename Other>
  ExtendedUnifiedCamera<Other> cast() const {
    return ExtendedUnifiedCamera<Other>(params_.template cast<Other>());
  }

 private:
  Params params_;
  Scalar w_{};
};

}  // namespace telesphere::calib
