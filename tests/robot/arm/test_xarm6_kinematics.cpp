// SPDX-License-Identifier: MIT
/// @brief xArm 6 kinematics: published zero pose and limits, Jacobian against central
///        differences, FK/IK round trips, continuity along a path, wrist and elbow singularities,
///        the workspace boundary and invalid targets.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include "robot/arm/xarm6_kinematics.h"
#include "tests/support/jacobian_check.h"

namespace telesphere::robot {
namespace {

constexpr double kDeg = M_PI / 180.0;

arm::JointVector randomJoints(const arm::Xarm6Kinematics& kin, std::mt19937& rng, double margin) {
  arm::JointVector q;
  for (int i = 0; i < 6; ++i) {
    std::uniform_real_distribution<double> u(kin.lowerLimits()[i] + margin,
                                             kin.upperLimits()[i] - margin);
    q[i] = u(rng);
  }
  return q;
}

double weightedCost(const Eigen::Isometry3d& T, const Eigen::Isometry3d& target, double w) {
  return (target.translation() - T.translation()).squaredNorm() +
         std::pow(w * arm::rotationLog(target.linear() * T.linear().transpose()).norm(), 2);
}

TEST(Xarm6Kinematics, ZeroPoseMatchesPublishedHome) {
  const arm::Xarm6Kinematics kin;
  const Eigen::Isometry3d T = kin.forward(arm::JointVector::Zero());
  EXPECT_NEAR(T.translation().x(), 0.207, 1e-4);
  EXPECT_NEAR(T.translation().y(), 0.0, 1e-9);
  EXPECT_NEAR(T.translation().z(), 0.112, 1e-4);
  // Roll 180°: flange z points down, flange x forward.
  EXPECT_TRUE(T.linear().isApprox(Eigen::Matrix3d(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())),
                                  1e-9))
      << T.linear();
}

TEST(Xarm6Kinematics, PublishedJointLimits) {
  const arm::Xarm6Kinematics kin;
  arm::JointVector lower, upper;
  lower << -360, -118, -225, -360, -97, -360;
  upper << 360, 120, 11, 360, 180, 360;
  EXPECT_TRUE(kin.lowerLimits().isApprox(lower * kDeg, 1e-12));
  EXPECT_TRUE(kin.upperLimits().isApprox(upper * kDeg, 1e-12));
  arm::JointVector q = arm::JointVector::Zero();
  q[1] = 121 * kDeg;
  EXPECT_FALSE(kin.withinLimits(q));
  EXPECT_NEAR(kin.clampToLimits(q)[1], 120 * kDeg, 1e-12);
  q[1] = NAN;
  EXPECT_FALSE(kin.withinLimits(q));
  EXPECT_TRUE(kin.withinLimits(kin.clampToLimits(q)));
}

TEST(Xarm6Kinematics, JacobianMatchesCentralDifferences) {
  const arm::Xarm6Kinematics kin;
  std::mt19937 rng(7);
  for (int n = 0; n < 50; ++n) {
    const arm::JointVector q0 = randomJoints(kin, rng, 0.0);
    arm::Jacobian6 J;
    const Eigen::Isometry3d T0 = kin.forward(q0, &J);
    const auto f = [&](const Eigen::VectorXd& q) {
      const Eigen::Isometry3d T = kin.forward(q);
      Eigen::VectorXd out(6);
      out << T.translation(), arm::rotationLog(T.linear() * T0.linear().transpose());
      return out;
    };
    EXPECT_TRUE(test::jacobianNear(J, test::numericJacobian(f, q0), 1e-6)) << "q = " << q0.transpose();
  }
}

TEST(Xarm6Kinematics, IkRoundTripFromNearbySeed) {
  const arm::Xarm6Kinematics kin;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> perturb(-0.2, 0.2);
  int tried = 0;
  while (tried < 300) {
    const arm::JointVector q_true = randomJoints(kin, rng, 5 * kDeg);
    if (kin.minSingularValue(q_true) < 0.02) continue;  // singular cases have their own tests
    ++tried;
    arm::JointVector seed = q_true;
    for (int i = 0; i < 6; ++i) seed[i] += perturb(rng);
    const Eigen::Isometry3d target = kin.forward(q_true);
    const arm::IkResult r = kin.inverse(target, seed);
    ASSERT_TRUE(r.converged()) << "q_true " << q_true.transpose() << " pos err "
                               << r.position_error << " angle err " << r.angle_error;
    const Eigen::Isometry3d T = kin.forward(r.q);
    EXPECT_LT((T.translation() - target.translation()).norm(), 1e-6);
    EXPECT_LT(arm::rotationLog(T.linear() * target.linear().transpose()).norm(), 1e-6);
    EXPECT_TRUE(kin.withinLimits(r.q));
    // Same branch as the configuration near the seed.
    EXPECT_LT((r.q - q_true).cwiseAbs().maxCoeff(), 0.5) << r.q.transpose() << " vs " << q_true.transpose();
  }
}

TEST(Xarm6Kinematics, IkContinuousAlongPath) {
  const arm::Xarm6Kinematics kin;
  arm::JointVector q;
  q << 0.1, -0.3, -1.2, 0.2, 1.0, 0.3;
  const Eigen::Isometry3d start = kin.forward(q);
  for (int k = 1; k <= 300; ++k) {
    Eigen::Isometry3d target = start;
    target.translation() += Eigen::Vector3d(0.0005 * k, 0.0008 * k, -0.0003 * k);
    target.linear() = start.linear() * Eigen::AngleAxisd(0.002 * k, Eigen::Vector3d::UnitY());
    const arm::IkResult r = kin.inverse(target, q);
    ASSERT_TRUE(r.converged()) << "step " << k;
    // ~1 mm and 0.1° per step: joints move by a comparable small amount, no branch flip.
    EXPECT_LT((r.q - q).cwiseAbs().maxCoeff(), 0.02) << "step " << k;
    q = r.q;
  }
}

TEST(Xarm6Kinematics, WristSingularity) {
  // The xArm 6 wrist is offset (a5 = 76 mm), so J5 = 0 only makes J4 and J6 parallel, not
  // coincident, and is not singular; the wrist singularity lies elsewhere along J5. Find it.
  const arm::Xarm6Kinematics kin;
  arm::JointVector q;
  q << 0.0, -0.4, -1.0, 0.3, 0.0, -0.2;
  EXPECT_GT(kin.minSingularValue(q), 0.01);  // J5 = 0
  double best_sigma = 1e9, best_q5 = 0;
  for (double q5 = kin.lowerLimits()[4]; q5 <= kin.upperLimits()[4]; q5 += 1e-4) {
    q[4] = q5;
    const double sigma = kin.minSingularValue(q);
    if (sigma < best_sigma) best_sigma = sigma, best_q5 = q5;
  }
  q[4] = best_q5;
  const arm::JointVector q_singular = q;
  EXPECT_LT(best_sigma, 1e-4);
  // A target at the singular configuration, from a nearby seed: reached.
  arm::JointVector seed = q_singular + arm::JointVector::Constant(0.05);
  const arm::IkResult at = kin.inverse(kin.forward(q_singular), seed);
  EXPECT_TRUE(at.converged()) << at.position_error << " " << at.angle_error;
  // From exactly on the singularity, towards 1 cm / 0.05 rad along the lost task direction
  // (the smallest singular vector): no NaN, no wild joint jump, error never worse than the start.
  arm::Jacobian6 J;
  const Eigen::Isometry3d T_singular = kin.forward(q_singular, &J);
  J.bottomRows<3>() *= arm::IkOptions{}.rotation_weight;
  const Eigen::SelfAdjointEigenSolver<arm::Jacobian6> eig(J * J.transpose());
  const Eigen::Matrix<double, 6, 1> lost = eig.eigenvectors().col(0);
  Eigen::Isometry3d target = T_singular;
  target.translation() += 0.01 * lost.head<3>().normalized();
  target.linear() = Eigen::AngleAxisd(0.05, lost.tail<3>().normalized()) * target.linear();
  const arm::IkResult away = kin.inverse(target, q_singular);
  ASSERT_TRUE(away.q.allFinite());
  EXPECT_TRUE(kin.withinLimits(away.q));
  EXPECT_LE(weightedCost(kin.forward(away.q), target, 0.2), weightedCost(T_singular, target, 0.2));
  // Moving along a lost direction needs large joint motion, but it stays bounded.
  EXPECT_LT((away.q - q_singular).cwiseAbs().maxCoeff(), 1.5) << away.q.transpose();
  if (away.converged()) {
    EXPECT_LT(away.position_error, 1e-6);
  } else {
    EXPECT_EQ(away.status, arm::IkResult::Status::kClosestReachable);
  }
}

TEST(Xarm6Kinematics, ElbowSingularityAndStretchedBoundary) {
  const arm::Xarm6Kinematics kin;
  // The elbow is stretched where q3 puts the forearm in line with the upper arm; find it.
  arm::JointVector q = arm::JointVector::Zero();
  q[4] = 0.8;
  double best_q3 = 0, best_sigma = 1e9;
  for (double q3 = kin.lowerLimits()[2]; q3 <= kin.upperLimits()[2]; q3 += 1e-4) {
    q[2] = q3;
    const double s = kin.minSingularValue(q);
    if (s < best_sigma) best_sigma = s, best_q3 = q3;
  }
  EXPECT_LT(best_sigma, 1e-3);
  q[2] = best_q3;
  // Shoulder to wrist centre (frame 5 origin) must be at its longest there.
  const double reach = 0.28948866 + std::hypot(0.0775, 0.3425);
  Eigen::Isometry3d T5 = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 5; ++i) {
    const arm::MdhLink& l = kin.links()[static_cast<std::size_t>(i)];
    T5 = T5 * Eigen::AngleAxisd(l.alpha, Eigen::Vector3d::UnitX()) * Eigen::Translation3d(l.a, 0, 0) *
         Eigen::AngleAxisd(q[i] + l.theta_offset, Eigen::Vector3d::UnitZ()) *
         Eigen::Translation3d(0, 0, l.d);
  }
  EXPECT_NEAR((T5.translation() - Eigen::Vector3d(0, 0, 0.267)).norm(), reach, 1e-5);
  // Ask for 5 cm further out along the arm: unreachable, flagged, closest pose finite and
  // within limits, stretched (≈ 5 cm short), seeded from the slightly bent arm.
  const Eigen::Isometry3d T_stretched = kin.forward(q);
  Eigen::Isometry3d target = T_stretched;
  const Eigen::Vector3d out_dir = (T5.translation() - Eigen::Vector3d(0, 0, 0.267)).normalized();
  target.translation() += 0.05 * out_dir;
  arm::JointVector seed = q;
  seed[2] -= 0.3;
  const arm::IkResult r = kin.inverse(target, seed);
  EXPECT_EQ(r.status, arm::IkResult::Status::kClosestReachable);
  EXPECT_TRUE(kin.withinLimits(r.q));
  EXPECT_NEAR(r.position_error, 0.05, 0.005);
  EXPECT_LT(r.angle_error, 0.05);
  // IK on the singularity itself (target = the stretched pose) converges.
  const arm::IkResult on = kin.inverse(T_stretched, seed);
  EXPECT_TRUE(on.converged()) << on.position_error << " " << on.angle_error;
}

TEST(Xarm6Kinematics, UnreachableTargetGivesClosestReachablePose) {
  const arm::Xarm6Kinematics kin;
  arm::IkOptions options;
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  target.translation() = Eigen::Vector3d(1.2, 0.5, 0.6);
  target.linear() = Eigen::Matrix3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  arm::JointVector seed;
  seed << 0.3, 0.2, -0.8, 0.0, 0.6, 0.0;
  const arm::IkResult r = kin.inverse(target, seed, options);
  EXPECT_EQ(r.status, arm::IkResult::Status::kClosestReachable);
  ASSERT_TRUE(r.q.allFinite());
  EXPECT_TRUE(kin.withinLimits(r.q));
  const double cost = weightedCost(kin.forward(r.q), target, options.rotation_weight);
  EXPECT_LT(cost, weightedCost(kin.forward(seed), target, options.rotation_weight));
  // No configuration in a dense random sample is closer.
  std::mt19937 rng(3);
  for (int n = 0; n < 20000; ++n) {
    const arm::JointVector q = randomJoints(kin, rng, 0.0);
    ASSERT_GE(weightedCost(kin.forward(q), target, options.rotation_weight), cost - 1e-9)
        << q.transpose();
  }
}

TEST(Xarm6Kinematics, JointLimitsHoldForTargetsBeyondThem) {
  const arm::Xarm6Kinematics kin;
  arm::JointVector beyond;
  beyond << 0.0, 125 * kDeg, -1.0, 0.0, 1.0, 0.0;  // J2 past its 120° limit
  arm::JointVector seed = beyond;
  seed[1] = 110 * kDeg;
  const arm::IkResult r = kin.inverse(kin.forward(beyond), seed);
  EXPECT_TRUE(kin.withinLimits(r.q)) << r.q.transpose();
  if (!r.converged()) {
    EXPECT_TRUE(r.at_joint_limit);
  }
}

TEST(Xarm6Kinematics, InvalidTargetReturnsClampedSeed) {
  const arm::Xarm6Kinematics kin;
  arm::JointVector seed = arm::JointVector::Zero();
  seed[1] = 2.5;  // beyond J2's limit
  Eigen::Isometry3d nan_target = Eigen::Isometry3d::Identity();
  nan_target.translation().x() = NAN;
  arm::IkResult r = kin.inverse(nan_target, seed);
  EXPECT_EQ(r.status, arm::IkResult::Status::kInvalidTarget);
  EXPECT_TRUE(r.q.isApprox(kin.clampToLimits(seed)));
  Eigen::Isometry3d skewed = Eigen::Isometry3d::Identity();
  skewed.linear()(0, 1) = 0.3;
  r = kin.inverse(skewed, seed);
  EXPECT_EQ(r.status, arm::IkResult::Status::kInvalidTarget);
}

}  // namespace
}  // namespace telesphere::robot
