// SPDX-License-Identifier: MIT
/// @brief Kannala-Brandt camera model with four radial terms, KB4 (Kannala & Brandt, PAMI 2006);
///        kalibr's "pinhole" + "equidistant", Basalt's "kb4", OpenCV's fisheye model.
///        Parameters [fx, fy, cx, cy, k1, k2, k3, k4], model name "kb4".
///
/// Projection of p = (x, y, z) in the optical frame (x right, y down, z forward):
///   r = sqrt(x² + y²),  θ = atan2(r, z),
///   θd = θ·(1 + k1·θ² + k2·θ⁴ + k3·θ⁶ + k4·θ⁸),
///   u = fx·θd·x/r + cx,  v = fy·θd·y/r + cy   (on the axis, θd/r → 1/z).
/// Valid iff θ < maxAngle() = θmax, the first angle in (0, π] where dθd/dθ = 0 (beyond it the
/// image folds back and unprojection is ambiguous), or π when θd rises all the way. θ = π (the
/// backward axis) has no direction and is never valid.
///
/// Unprojection: θ from θd(θ) = |(mx, my)| by safeguarded Newton on [0, θmax];
/// d = (sin θ·mx/rd, sin θ·my/rd, cos θ).
///
/// Parameter domain: fx, fy > 0; cx, cy finite; k1..k4 finite with |k_i| ≤ 10.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "calib/camera_model_support.h"
#include "calib/debug_assert.h"
#include "calib/scalar_math.h"

namespace telesphere::calib {

template <typename Scalar_>
class KannalaBrandtCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 8;
  static constexpr std::string_view kName = "kb4";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {
      "fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat2x3 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2xP = Eigen::Matrix<Scalar, 2, kNumParams>;

  explicit KannalaBrandtCamera(const Params& params) : params_(params) {
    const Eigen::Matrix<double, kNumParams, 1> v = valuesOf(params_);
    TS_ASSERT(!checkParams(v), *checkParams(v));
    const double theta_max = firstCriticalAngle(v[4], v[5], v[6], v[7]);
    theta_max_ = Scalar(theta_max);
    theta_d_max_ = Scalar(thetaD(theta_max, v[4], v[5], v[6], v[7]));
  }

  const Params& params() const { return params_; }

  static std::optional<std::string> checkParams(const Eigen::Matrix<double, kNumParams, 1>& p) {
    return firstError({checkPositive("fx", p[0]), checkPositive("fy", p[1]),
                       checkFinite("cx", p[2]), checkFinite("cy", p[3]),
                       checkClosed("k1", p[4], -10.0, 10.0), checkClosed("k2", p[5], -10.0, 10.0),
                       checkClosed("k3", p[6], -10.0, 10.0), checkClosed("k4", p[7], -10.0, 10.0)});
  }

  /// Largest angle (rad) from the optical axis that projects: θ < maxAngle().
  Scalar maxAngle() const { return theta_max_; }

  template <typename Derived>
  bool project(const Eigen::MatrixBase<Derived>& p_cam, Vec2& out_px, Mat2x3* d_px_d_p = nullptr,
               Mat2xP* d_px_d_params = nullptr) const {
    const Scalar& x = p_cam[0];
    const Scalar& y = p_cam[1];
    const Scalar& z = p_cam[2];
    const Scalar r2 = x * x + y * y;
    const Scalar z2 = z * z;
    const Scalar n2 = r2 + z2;
    if (!squaredNormInSafeRange(n2)) [[unlikely]]
      return projectRescaled(*this, p_cam, out_px, d_px_d_p, d_px_d_params);

    using std::atan2;
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& k1 = params_[4];
    const Scalar& k2 = params_[5];
    const Scalar& k3 = params_[6];
    const Scalar& k4 = params_[7];

    // On the axis θ/r is 0/0 (and sqrt'(0) breaks Jets): there use the series
    // θ = r/z − r³/(3z³) + O(r⁵), i.e. θ² ≈ r²/z² and q = θ/r ≈ (1 − r²/(3z²))/z.
    const bool on_axis = r2 < Scalar(scalarEpsilon<Scalar>()) * z2 && z > Scalar(0);
    Scalar t2, q;
    if (on_axis) {
      t2 = r2 / z2;
      q = (Scalar(1) - r2 / (Scalar(3) * z2)) / z;
    } else {
      const Scalar r = sqrt(r2);
      const Scalar theta = atan2(r, z);
      if (!(theta < theta_max_)) return invalidProject(out_px, d_px_d_p, d_px_d_params);
      t2 = theta * theta;
      q = theta / r;
    }
    const Scalar poly = Scalar(1) + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4)));
    const Scalar s = q * poly;  // θd/r
    out_px << fx * x * s + cx, fy * y * s + cy;

    if (d_px_d_p) {
      // ∂s/∂x = x·A, ∂s/∂y = y·A, ∂s/∂z = ds_dz.
      Scalar a, ds_dz;
      if (on_axis) {
        a = Scalar(2) * (k1 - Scalar(1.0 / 3.0)) / (z2 * z);
        ds_dz = Scalar(-1) / z2;
      } else {
        const Scalar dthetad = Scalar(1) + t2 * (Scalar(3) * k1 +
                                                 t2 * (Scalar(5) * k2 +
                                                       t2 * (Scalar(7) * k3 + t2 * Scalar(9) * k4)));
        a = (dthetad * z / n2 - s) / r2;
        ds_dz = -dthetad / n2;
      }
      auto& J = *d_px_d_p;
      J(0, 0) = fx * (s + x * x * a);
      J(0, 1) = fx * x * y * a;
      J(0, 2) = fx * x * ds_dz;
      J(1, 0) = fy * x * y * a;
      J(1, 1) = fy * (s + y * y * a);
      J(1, 2) = fy * y * ds_dz;
    }
    if (d_px_d_params) {
      auto& J = *d_px_d_params;
      J.setZero();
      J(0, 0) = x * s;
      J(0, 2) = Scalar(1);
      J(1, 1) = y * s;
      J(1, 3) = Scalar(1);
      Scalar t_pow = q * t2;  // ∂s/∂k_i = q·θ^(2i)
      for (int i = 0; i < 4; ++i) {
        J(0, 4 + i) = fx * x * t_pow;
        J(1, 4 + i) = fy * y * t_pow;
        t_pow *= t2;
      }
    }
    return true;
  }

  template <typename Derived>
  bool unproject(const Eigen::MatrixBase<Derived>& px, Vec3& out_d_cam) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Scalar& k1 = params_[4];
    const Scalar& k2 = params_[5];
    const Scalar& k3 = params_[6];
    const Scalar& k4 = params_[7];
    const Scalar mx = (px[0] - params_[2]) / params_[0];
    const Scalar my = (px[1] - params_[3]) / params_[1];
    const Scalar rd2 = mx * mx + my * my;
    const Scalar rd = sqrt(rd2);
    if (!(isFiniteScalar(rd) && rd < theta_d_max_)) return invalidUnproject(out_d_cam);

    // θd(θ) rises on [0, θmax]: solve θd(θ) = rd there.
    const auto eval = [&](const Scalar& t) {
      const Scalar t2 = t * t;
      const Scalar g = t * (Scalar(1) + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
      const Scalar dg = Scalar(1) + t2 * (Scalar(3) * k1 +
                                          t2 * (Scalar(5) * k2 +
                                                t2 * (Scalar(7) * k3 + t2 * Scalar(9) * k4)));
      return std::pair<Scalar, Scalar>(g, dg);
    };
    const Scalar theta = solveIncreasing(eval, rd, Scalar(0), theta_max_,
                                         rd < theta_max_ ? rd : Scalar(0.5) * theta_max_);
    if (!(theta >= Scalar(0) && theta < theta_max_)) return invalidUnproject(out_d_cam);
    // sin θ/rd, with its limit 1 at the centre.
    const Scalar f = rd > Scalar(scalarEpsilon<Scalar>()) ? sin(theta) / rd : Scalar(1);
    out_d_cam << f * mx, f * my, cos(theta);
    return true;
  }

  template <typename Other>
  KannalaBrandtCamera<Other> cast() const {
    return KannalaBrandtCamera<Other>(params_.template cast<Other>());
  }

 private:
  static double thetaD(double t, double k1, double k2, double k3, double k4) {
    const double t2 = t * t;
    return t * (1 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
  }

  /// First θ in (0, π] with dθd/dθ = 0 (bisection after a fine scan), π if there is none.
  static double firstCriticalAngle(double k1, double k2, double k3, double k4) {
    auto dthetad = [&](double t) {
      const double t2 = t * t;
      return 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4)));
    };
    constexpr double kPi = 3.14159265358979323846;
    constexpr int kSteps = 4096;
    double prev = 0.0;
    for (int i = 1; i <= kSteps; ++i) {
      const double t = kPi * i / kSteps;
      if (!(dthetad(t) > 0.0)) {
        double lo = prev, hi = t;
        for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
          const double mid = 0.5 * (lo + hi);
          (dthetad(mid) > 0.0 ? lo : hi) = mid;
        }
        return lo;
      }
      prev = t;
    }
    return kPi;
  }

  Params params_;
  Scalar theta_max_{};
  Scalar theta_d_max_{};
};

}  // namespace telesphere::calib
