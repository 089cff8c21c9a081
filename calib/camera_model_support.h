// SPDX-License-Identifier: MIT
/// @brief What every camera model shares: parameter-domain checks that name the parameter, the
///        zeroed outputs of an invalid projection, and the rescaling of points whose squared norm
///        would under- or overflow (projection is invariant to a point's scale).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <algorithm>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "calib/scalar_math.h"

namespace telesphere::calib {

inline std::optional<std::string> checkFinite(const char* name, double value) {
  if (std::isfinite(value)) return std::nullopt;
  std::ostringstream os;
  os << name << " = " << value << " is not a finite number";
  return os.str();
}

inline std::optional<std::string> checkPositive(const char* name, double value) {
  if (std::isfinite(value) && value > 0.0) return std::nullopt;
  std::ostringstream os;
  os << name << " = " << value << " must be a finite number > 0";
  return os.str();
}

/// value ∈ [lo, hi]
inline std::optional<std::string> checkClosed(const char* name, double value, double lo, double hi) {
  if (value >= lo && value <= hi) return std::nullopt;
  std::ostringstream os;
  os.precision(17);
  os << name << " = " << value << " is outside [" << lo << ", " << hi << "]";
  return os.str();
}

/// value ∈ (lo, hi]
inline std::optional<std::string> checkOpenClosed(const char* name, double value, double lo,
                                                  double hi) {
  if (value > lo && value <= hi) return std::nullopt;
  std::ostringstream os;
  os.precision(17);
  os << name << " = " << value << " is outside (" << lo << ", " << hi << "]";
  return os.str();
}

inline std::optional<std::string> firstError(
    std::initializer_list<std::optional<std::string>> checks) {
  for (const auto& c : checks)
    if (c) return c;
  return std::nullopt;
}

/// The values of a parameter vector as doubles (the real part of Jets).
template <typename Scalar, int N>
Eigen::Matrix<double, N, 1> valuesOf(const Eigen::Matrix<Scalar, N, 1>& params) {
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = scalarValue(params[i]);
  return v;
}

/// Zeroes the outputs of a projection that is not valid and returns false.
template <typename Vec2, typename MatP, typename MatParams>
bool invalidProject(Vec2& out_px, MatP* d_px_d_p, MatParams* d_px_d_params) {
  out_px.setZero();
  if (d_px_d_p) d_px_d_p->setZero();
  if (d_px_d_params) d_px_d_params->setZero();
  return false;
}

/// Zeroes the output of an unprojection that is not valid and returns false.
template <typename Vec3>
bool invalidUnproject(Vec3& out_d) {
  out_d.setZero();
  return false;
}

/// Projects a point whose squared norm is outside the safe range by dividing it by its largest
/// absolute coordinate s first; d_px_d_p is scaled back by 1/s. The camera centre, NaN and inf are
/// invalid.
template <typename Camera, typename Derived>
bool projectRescaled(const Camera& camera, const Eigen::MatrixBase<Derived>& p,
                     typename Camera::Vec2& out_px, typename Camera::Mat2x3* d_px_d_p,
                     typename Camera::Mat2xP* d_px_d_params) {
  using Scalar = typename Camera::Scalar;
  using std::abs;
  if (!(isFiniteScalar(p[0]) && isFiniteScalar(p[1]) && isFiniteScalar(p[2])))
    return invalidProject(out_px, d_px_d_p, d_px_d_params);
  const Scalar s = std::max({abs(p[0]), abs(p[1]), abs(p[2])});
  if (!(s > Scalar(0) && isFiniteScalar(s))) return invalidProject(out_px, d_px_d_p, d_px_d_params);
  const typename Camera::Vec3 q(p[0] / s, p[1] / s, p[2] / s);
  if (!camera.project(q, out_px, d_px_d_p, d_px_d_params)) return false;
  if (d_px_d_p) *d_px_d_p /= s;
  return true;
}

/// Solves g(t) = target for t ∈ [lo, hi] where g rises strictly, by Newton's method kept inside
/// the shrinking bracket (bisection whenever a step leaves it or |g − target| does not halve).
/// eval(t) returns {g(t), g'(t)}. It ends with one Newton step so that for ceres::Jet the result
/// carries the implicit derivative −(∂g/∂params)/g'.
template <typename Scalar, typename Eval>
Scalar solveIncreasing(const Eval& eval, const Scalar& target, Scalar lo, Scalar hi, Scalar t) {
  using std::abs;
  const double tol = 4.0 * scalarEpsilon<Scalar>();
  double prev_residual = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 200; ++it) {
    const auto [g, dg] = eval(t);
    const Scalar f = g - target;
    const double residual = std::abs(scalarValue(f));
    if (residual <= tol * (1.0 + std::abs(scalarValue(target)))) break;
    if (f > Scalar(0)) {
      hi = t;
    } else {
      lo = t;
    }
    Scalar next = t - f / dg;
    if (!(next > lo && next < hi) || residual > 0.5 * prev_residual) next = Scalar(0.5) * (lo + hi);
    prev_residual = residual;
    t = next;
    if (scalarValue(hi) - scalarValue(lo) <= tol * (1.0 + std::abs(scalarValue(t)))) break;
  }
  const auto [g, dg] = eval(t);
  return t - (g - target) / dg;
}

}  // namespace telesphere::calib
