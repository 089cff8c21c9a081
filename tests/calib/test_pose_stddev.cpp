// SPDX-License-Identifier: MIT
/// @brief The covariance of an inverted pose (calib/pose_stddev.h) against numeric differences of
///        T⁻¹ under exp-perturbations, for seeded random poses and covariances, at a pose with no
///        turn and at translations from 1 mm to 1 km.
#include <gtest/gtest.h>

#include <random>

#include "calib/pose_stddev.h"

namespace telesphere::calib {
namespace {

Eigen::Matrix3d expSo3(const Eigen::Vector3d& theta) {
  const double angle = theta.norm();
  return angle == 0 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(angle, theta / angle).toRotationMatrix();
}

/// d(θ_b, t_b_a)/d(θ_a, t_a_b) by central differences of the perturbed pose's inverse.
PoseCovariance numericJacobian(const Eigen::Isometry3d& T_a_b) {
  const Eigen::Isometry3d T_b_a = T_a_b.inverse();
  PoseCovariance J;
  for (int k = 0; k < 6; ++k) {
    const double h = 1e-6 * (k < 3 ? 1.0 : std::max(1.0, T_a_b.translation().norm()));
    Eigen::Matrix<double, 6, 1> out[2];
    for (int s = 0; s < 2; ++s) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      d[k] = s == 0 ? h : -h;
      Eigen::Isometry3d T = T_a_b;
      T.linear() = expSo3(d.head<3>()) * T_a_b.linear();
      T.translation() += d.tail<3>();
      const Eigen::Isometry3d T_inv = T.inverse();
      const Eigen::AngleAxisd turn(T_inv.linear() * T_b_a.linear().transpose());
      out[s].head<3>() = turn.angle() * turn.axis();
      out[s].tail<3>() = T_inv.translation() - T_b_a.translation();
    }
    J.col(k) = (out[0] - out[1]) / (2 * h);
  }
  return J;
}

PoseCovariance randomCovariance(std::mt19937& rng, double rotation_rad, double translation_m) {
  std::normal_distribution<double> n(0, 1);
  PoseCovariance A;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) A(i, j) = n(rng) * (i < 3 ? rotation_rad : translation_m);
  return A * A.transpose();  // correlated, positive semi-definite
}

void expectMatchesNumeric(const Eigen::Isometry3d& T_a_b, const PoseCovariance& cov) {
  const PoseCovariance J = numericJacobian(T_a_b);
  const PoseCovariance want = J * cov * J.transpose();
  const PoseCovariance got = inversePoseCovariance(T_a_b, cov);
  const double scale = want.cwiseAbs().maxCoeff();
  EXPECT_LT((got - want).cwiseAbs().maxCoeff(), 1e-6 * scale) << "t = " << T_a_b.translation().transpose() << "\n"
                                                               << got << "\nvs\n" << want;
}

TEST(PoseStddev, InverseCovarianceMatchesNumericDifferences) {
  std::mt19937 rng(41);
  std::normal_distribution<double> n(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSo3(Eigen::Vector3d(n(rng), n(rng), n(rng)));
    T.translation() = Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.1;
    expectMatchesNumeric(T, randomCovariance(rng, 1e-3, 1e-3));
  }
}

TEST(PoseStddev, InverseCovarianceAtTheExtremes) {
  std::mt19937 rng(42);
  // No turn, no translation: the inverse only flips signs, the variances stay.
  const PoseCovariance cov = randomCovariance(rng, 1e-4, 1e-3);
  const PoseCovariance same = inversePoseCovariance(Eigen::Isometry3d::Identity(), cov);
  EXPECT_LT((same - cov).cwiseAbs().maxCoeff(), 1e-15);
  // Translations from 1 mm to 1 km: the rotation's lever arm grows with them.
  for (const double length : {1e-3, 1.0, 1e3}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSo3(Eigen::Vector3d(0.3, -1.2, 2.9));
    T.translation() = Eigen::Vector3d(1, -2, 0.5).normalized() * length;
    expectMatchesNumeric(T, randomCovariance(rng, 1e-5, 1e-4));
  }
  // A rotation variance alone about an axis across a 1 m translation moves the inverse's origin
  // by that angle's σ times 1 m.
  PoseCovariance turn_only = PoseCovariance::Zero();
  turn_only(2, 2) = 1e-6;  // σ 1 mrad about z
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1, 0, 0);
  const PoseStddev sd = poseStddev(inversePoseCovariance(T, turn_only));
  ASSERT_TRUE(sd.valid);
  EXPECT_NEAR(sd.translation_m.y(), 1e-3, 1e-12);
  EXPECT_NEAR(sd.translation_m.x(), 0.0, 1e-12);
  EXPECT_NEAR(sd.rotation_deg.z(), 1e-3 * 180 / M_PI, 1e-12);
}

TEST(PoseStddev, NotValidWhenACovarianceIsNotFinite) {
  PoseCovariance cov = PoseCovariance::Identity() * 1e-6;
  cov(4, 4) = NAN;
  EXPECT_FALSE(poseStddev(cov).valid);
  EXPECT_TRUE(poseStddev(PoseCovariance::Identity() * 1e-6).valid);
}

}  // namespace
}  // namespace telesphere::calib
