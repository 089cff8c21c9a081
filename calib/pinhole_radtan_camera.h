// SPDX-License-Identifier: MIT
/// @brief Pinhole camera with radial-tangential distortion (Brown-Conrady, OpenCV's k1 k2 p1 p2;
///        kalibr's "pinhole" + "radtan" [k1, k2, r1, r2]). Parameters
///        [fx, fy, cx, cy, k1, k2, p1, p2], model name "pinhole"; all-zero distortion is the ideal
///        pinhole. For lenses below ~120° that need nothing more.
///
/// Projection of p = (x, y, z) in the optical frame (x right, y down, z forward):
///   a = x/z, b = y/z, r² = a² + b², R = 1 + k1·r² + k2·r⁴,
///   xd = a·R + 2·p1·a·b + p2·(r² + 2a²),  yd = b·R + p1·(r² + 2b²) + 2·p2·a·b,
///   u = fx·xd + cx,  v = fy·yd + cy.
/// Valid iff z > 0 and r² < r²max: the first r² where the radial map r·R(r²) stops rising
/// (d/dr = 1 + 3·k1·r² + 5·k2·r⁴ = 0), +∞ when it never does, shrunk where tangential terms
/// could fold the image (see injectiveLimitSquared). maxAngle() = atan(r_max) < π/2.
///
/// Unprojection: Newton on (a, b) from (mx, my), valid when it converges inside r²max.
///
/// Parameter domain: fx, fy > 0; cx, cy finite; k1, k2 ∈ [−10, 10]; p1, p2 ∈ [−1, 1].
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "calib/camera_model_support.h"
#include "calib/debug_assert.h"
#include "calib/scalar_math.h"

namespace telesphere::calib {

template <typename Scalar_>
class PinholeRadtanCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 8;
  static constexpr std::string_view kName = "pinhole";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {
      "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat2x3 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2xP = Eigen::Matrix<Scalar, 2, kNumParams>;

  explicit PinholeRadtanCamera(const Params& params) : params_(params) {
    const Eigen::Matrix<double, kNumParams, 1> v = valuesOf(params_);
    TS_ASSERT(!checkParams(v), *checkParams(v));
    r2_max_ = Scalar(injectiveLimitSquared(v[4], v[5], v[6], v[7]));
  }

  const Params& params() const { return params_; }

  static std::optional<std::string> checkParams(const Eigen::Matrix<double, kNumParams, 1>& p) {
    return firstError({checkPositive("fx", p[0]), checkPositive("fy", p[1]),
                       checkFinite("cx", p[2]), checkFinite("cy", p[3]),
                       checkClosed("k1", p[4], -10.0, 10.0), checkClosed("k2", p[5], -10.0, 10.0),
                       checkClosed("p1", p[6], -1.0, 1.0), checkClosed("p2", p[7], -1.0, 1.0)});
  }

  /// Largest angle (rad) from the optical axis that projects: θ < maxAngle() (< π/2).
  Scalar maxAngle() const {
    using std::atan;
    using std::sqrt;
    return atan(sqrt(r2_max_));
  }

  template <typename Derived>
  bool project(const Eigen::MatrixBase<Derived>& p_cam, Vec2& out_px, Mat2x3* d_px_d_p = nullptr,
               Mat2xP* d_px_d_params = nullptr) const {
    const Scalar& x = p_cam[0];
    const Scalar& y = p_cam[1];
    const Scalar& z = p_cam[2];
    if (!(z > Scalar(0) && isFiniteScalar(z))) return invalidProject(out_px, d_px_d_p, d_px_d_params);
    const Scalar inv_z = Scalar(1) / z;
    const Scalar a = x * inv_z;
    const Scalar b = y * inv_z;
    const Scalar r2 = a * a + b * b;
    if (!(r2 < r2_max_)) return invalidProject(out_px, d_px_d_p, d_px_d_params);

    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Vec2 d = distort(a, b);
    out_px << fx * d[0] + params_[2], fy * d[1] + params_[3];
    if (!(isFiniteScalar(out_px[0]) && isFiniteScalar(out_px[1])))
      return invalidProject(out_px, d_px_d_p, d_px_d_params);

    if (d_px_d_p) {
      const Eigen::Matrix<Scalar, 2, 2> J_d = distortJacobian(a, b);
      Eigen::Matrix<Scalar, 2, 3> J_ab;
      J_ab << inv_z, Scalar(0), -a * inv_z, Scalar(0), inv_z, -b * inv_z;
      *d_px_d_p = (Eigen::Matrix<Scalar, 2, 1>(fx, fy).asDiagonal() * J_d) * J_ab;
    }
    if (d_px_d_params) {
      auto& J = *d_px_d_params;
      J.setZero();
      J(0, 0) = d[0];
      J(0, 2) = Scalar(1);
      J(1, 1) = d[1];
      J(1, 3) = Scalar(1);
      J(0, 4) = fx * a * r2;
      J(1, 4) = fy * b * r2;
      J(0, 5) = fx * a * r2 * r2;
      J(1, 5) = fy * b * r2 * r2;
      J(0, 6) = fx * Scalar(2) * a * b;
      J(1, 6) = fy * (r2 + Scalar(2) * b * b);
      J(0, 7) = fx * (r2 + Scalar(2) * a * a);
      J(1, 7) = fy * Scalar(2) * a * b;
    }
    return true;
  }

  template <typename Derived>
  bool unproject(const Eigen::MatrixBase<Derived>& px, Vec3& out_d_cam) const {
    using std::sqrt;
    const Vec2 m((px[0] - params_[2]) / params_[0], (px[1] - params_[3]) / params_[1]);
    if (!(isFiniteScalar(m[0]) && isFiniteScalar(m[1]))) return invalidUnproject(out_d_cam);
    // Radial part first (r·R(r²) rises on [0, r_max)), then Newton on the full map from there.
    const Scalar rd = sqrt(m.squaredNorm());
    const auto radial = [&](const Scalar& r) {
      const Scalar r2 = r * r;
      return std::pair<Scalar, Scalar>(
          r * (Scalar(1) + r2 * (params_[4] + r2 * params_[5])),
          Scalar(1) + r2 * (Scalar(3) * params_[4] + Scalar(5) * params_[5] * r2));
    };
    Scalar hi = sqrt(r2_max_);
    if (!isFiniteScalar(hi)) {
      hi = rd > Scalar(1) ? rd : Scalar(1);
      for (int i = 0; i < 64 && !(radial(hi).first > rd); ++i) hi *= Scalar(2);
    }
    // Start on the radial solution, inside the valid disc r² < r²max.
    Vec2 ab = m;
    if (rd > Scalar(0)) {
      const Scalar r = rd < radial(hi).first
                           ? solveIncreasing(radial, rd, Scalar(0), hi, rd < hi ? rd : Scalar(0.5) * hi)
                           : Scalar(0.999) * hi;
      ab *= r / rd;
    }
    const double tol2 = 64.0 * scalarEpsilon<Scalar>() * scalarEpsilon<Scalar>() *
                        (1.0 + scalarValue(m.squaredNorm()));
    // Newton on the full map, steps shortened to stay inside the disc (where the map is one to
    // one), so it cannot wander onto the folded branch.
    bool converged = false;
    for (int it = 0; it < 40 && !converged; ++it) {
      const Vec2 residual = distort(ab[0], ab[1]) - m;
      converged = scalarValue(residual.squaredNorm()) <= tol2;
      const Eigen::Matrix<Scalar, 2, 2> J = distortJacobian(ab[0], ab[1]);
      const Scalar det = J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0);
      Vec2 step((J(1, 1) * residual[0] - J(0, 1) * residual[1]) / det,
                (J(0, 0) * residual[1] - J(1, 0) * residual[0]) / det);
      if (!(isFiniteScalar(step[0]) && isFiniteScalar(step[1]))) return invalidUnproject(out_d_cam);
      for (int halve = 0; halve < 30 && !((ab - step).squaredNorm() < r2_max_); ++halve)
        step *= Scalar(0.5);
      ab -= step;
    }
    if (!converged || !(ab.squaredNorm() < r2_max_)) return invalidUnproject(out_d_cam);
    const Scalar inv_norm = Scalar(1) / sqrt(ab.squaredNorm() + Scalar(1));
    out_d_cam << ab[0] * inv_norm, ab[1] * inv_norm, inv_norm;
    return true;
  }

  template <typename Other>
  PinholeRadtanCamera<Other> cast() const {
    return PinholeRadtanCamera<Other>(params_.template cast<Other>());
  }

 private:
  Vec2 distort(const Scalar& a, const Scalar& b) const {
    const Scalar& k1 = params_[4];
    const Scalar& k2 = params_[5];
    const Scalar& p1 = params_[6];
    const Scalar& p2 = params_[7];
    const Scalar r2 = a * a + b * b;
    const Scalar radial = Scalar(1) + r2 * (k1 + r2 * k2);
    const Scalar ab2 = Scalar(2) * a * b;
    return Vec2(a * radial + p1 * ab2 + p2 * (r2 + Scalar(2) * a * a),
                b * radial + p1 * (r2 + Scalar(2) * b * b) + p2 * ab2);
  }

  Eigen::Matrix<Scalar, 2, 2> distortJacobian(const Scalar& a, const Scalar& b) const {
    const Scalar& k1 = params_[4];
    const Scalar& k2 = params_[5];
    const Scalar& p1 = params_[6];
    const Scalar& p2 = params_[7];
    const Scalar r2 = a * a + b * b;
    const Scalar radial = Scalar(1) + r2 * (k1 + r2 * k2);
    const Scalar dradial_dr2 = k1 + Scalar(2) * k2 * r2;
    const Scalar cross = Scalar(2) * a * b * dradial_dr2 + Scalar(2) * p1 * a + Scalar(2) * p2 * b;
    Eigen::Matrix<Scalar, 2, 2> J;
    J << radial + Scalar(2) * a * a * dradial_dr2 + Scalar(2) * p1 * b + Scalar(6) * p2 * a, cross,
        cross, radial + Scalar(2) * b * b * dradial_dr2 + Scalar(6) * p1 * b + Scalar(2) * p2 * a;
    return J;
  }

  /// The largest r² within the radial limit on which the whole map is one to one: the radial
  /// part G has smallest singular value σ(r) = min(g'(r), g(r)/r) with g(r) = r·R(r²), the
  /// tangential part T is Lipschitz with L·R on the disc of radius R, so F = G + T is injective
  /// while L·R < min over r ≤ R of σ(r). (Sufficient, so slightly conservative; exact for
  /// p1 = p2 = 0.)
  static double injectiveLimitSquared(double k1, double k2, double p1, double p2) {
    const double r2_radial = radialLimitSquared(k1, k2);
    if (p1 == 0.0 && p2 == 0.0) return r2_radial;
    const double a1 = std::abs(p1), a2 = std::abs(p2);
    const double lipschitz = std::sqrt((2 * a1 + 6 * a2) * (2 * a1 + 6 * a2) +
                                       8 * (a1 + a2) * (a1 + a2) +
                                       (6 * a1 + 2 * a2) * (6 * a1 + 2 * a2));
    const auto sigma = [&](double r) {
      const double r2 = r * r;
      return std::min(1 + r2 * (3 * k1 + 5 * k2 * r2), 1 + r2 * (k1 + k2 * r2));
    };
    const double r_end = std::sqrt(std::min(r2_radial, 1e4));
    constexpr int kSteps = 2048;
    double min_sigma = 1.0;
    for (int i = 1; i <= kSteps; ++i) {
      const double r = r_end * i / kSteps;
      min_sigma = std::min(min_sigma, sigma(r));
      if (!(lipschitz * r < min_sigma)) {
        const double r_ok = r_end * (i - 1) / kSteps;
        return r_ok * r_ok;
      }
    }
    return r2_radial;
  }

  /// First r² > 0 where 1 + 3·k1·r² + 5·k2·r⁴ = 0 (the radial map stops rising), else +∞.
  static double radialLimitSquared(double k1, double k2) {
    const double a = 5.0 * k2, b = 3.0 * k1, c = 1.0;
    double best = std::numeric_limits<double>::infinity();
    if (a == 0.0) {
      if (b < 0.0) best = -c / b;
      return best;
    }
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return best;
    const double sq = std::sqrt(disc);
    // Numerically stable roots of a·s² + b·s + c.
    const double q = -0.5 * (b + (b >= 0.0 ? sq : -sq));
    for (const double s : {q / a, c / q})
      if (s > 0.0 && s < best) best = s;
    return best;
  }

  Params params_;
  Scalar r2_max_{};
};

}  // namespace telesphere::calib
