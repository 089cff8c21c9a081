// SPDX-License-Identifier: MIT
/// @brief Jacobians against central differences, one helper for every test (STYLE.md §18):
///        a failure prints both matrices.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <functional>
#include <sstream>

namespace telesphere::test {

/// Central-difference Jacobian of f: R^n → R^m at x with step h (relative to |x_i|, at least h).
inline Eigen::MatrixXd numericJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    const double step = h * std::max(1.0, std::abs(x[i]));
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += step;
    xm[i] -= step;
    J.col(i) = (f(xp) - f(xm)) / (2.0 * step);
  }
  return J;
}

/// Passes when |analytic − numeric| ≤ tol·(1 + |numeric|) elementwise.
inline ::testing::AssertionResult jacobianNear(const Eigen::MatrixXd& analytic,
                                               const Eigen::MatrixXd& numeric, double tol) {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols())
    return ::testing::AssertionFailure() << "shape mismatch";
  const Eigen::MatrixXd err = (analytic - numeric).cwiseAbs();
  const Eigen::MatrixXd bound = (numeric.cwiseAbs().array() + 1.0).matrix() * tol;
  if (((err - bound).array() <= 0.0).all()) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os << "\nanalytic:\n" << analytic << "\nnumeric:\n" << numeric << "\n|difference|:\n" << err;
  return ::testing::AssertionFailure() << os.str();
}

}  // namespace telesphere::test
