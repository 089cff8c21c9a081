// SPDX-License-Identifier: MIT
/// @brief UFACTORY xArm 6 kinematics (see xarm6_kinematics.h for the parameters and sources).
#include "robot/arm/xarm6_kinematics.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "calib/debug_assert.h"

namespace telesphere::robot::arm {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// Weighted pose error [p_t − p; w·log(R_t Rᵀ)] and its squared norm; J_w the weighted Jacobian.
struct Residual {
  Vector6 e;
  Jacobian6 J_w;
  double cost = 0, position_error = 0, angle_error = 0;
};

}  // namespace

Eigen::Vector3d rotationLog(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond quat(R);
  if (quat.w() < 0) quat.coeffs() = -quat.coeffs();
  const Eigen::Vector3d v = quat.vec();
  const double n = v.norm();
  if (n < 1e-12) return 2.0 * v;  // first order; exact to rounding at this size
  return (2.0 * std::atan2(n, quat.w()) / n) * v;
}

bool isRotation(const Eigen::Matrix3d& R, double tol) {
  if (!R.allFinite()) return false;
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > tol) return false;
  return R.determinant() > 0;
}

Xarm6Kinematics::Xarm6Kinematics() {
  const double offset2 = std::atan2(284.5, 53.5);  // 1.3849179 rad
  const double a2 = std::hypot(284.5, 53.5) * 1e-3;  // 0.28948866 m
  links_ = {{{0.0, 0.0, 0.267, 0.0},
             {-kPi / 2, 0.0, 0.0, -offset2},
             {0.0, a2, 0.0, offset2},
             {-kPi / 2, 0.0775, 0.3425, 0.0},
             {kPi / 2, 0.0, 0.0, 0.0},
             {-kPi / 2, 0.076, 0.097, 0.0}}};
  lower_ << -360 * kDeg, -118 * kDeg, -225 * kDeg, -360 * kDeg, -97 * kDeg, -360 * kDeg;
  upper_ << 360 * kDeg, 120 * kDeg, 11 * kDeg, 360 * kDeg, 180 * kDeg, 360 * kDeg;
}

bool Xarm6Kinematics::withinLimits(const JointVector& q, double tol) const {
  for (int i = 0; i < kDof; ++i) {
    if (!std::isfinite(q[i]) || q[i] < lower_[i] - tol || q[i] > upper_[i] + tol) return false;
  }
  return true;
}

JointVector Xarm6Kinematics::clampToLimits(const JointVector& q) const {
  JointVector out;
  for (int i = 0; i < kDof; ++i) {
    out[i] = std::isfinite(q[i]) ? std::clamp(q[i], lower_[i], upper_[i])
                                 : 0.5 * (lower_[i] + upper_[i]);
  }
  return out;
}

Eigen::Isometry3d Xarm6Kinematics::forward(const JointVector& q, Jacobian6* d_pose_d_q) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  std::array<Eigen::Vector3d, kDof> origin, axis;
  for (int i = 0; i < kDof; ++i) {
    const MdhLink& l = links_[static_cast<std::size_t>(i)];
    T = T * Eigen::AngleAxisd(l.alpha, Eigen::Vector3d::UnitX());
    T = T * Eigen::Translation3d(l.a, 0, 0);
    T = T * Eigen::AngleAxisd(q[i] + l.theta_offset, Eigen::Vector3d::UnitZ());
    T = T * Eigen::Translation3d(0, 0, l.d);
    // Joint i turns about z_i through the origin of frame i (TransZ(d) stays on that line).
    origin[static_cast<std::size_t>(i)] = T.translation();
    axis[static_cast<std::size_t>(i)] = T.linear().col(2);
  }
  if (d_pose_d_q) {
    const Eigen::Vector3d p = T.translation();
    for (int i = 0; i < kDof; ++i) {
      const auto k = static_cast<std::size_t>(i);
      d_pose_d_q->block<3, 1>(0, i) = axis[k].cross(p - origin[k]);
      d_pose_d_q->block<3, 1>(3, i) = axis[k];
    }
  }
  return T;
}

double Xarm6Kinematics::minSingularValue(const JointVector& q, double rotation_weight) const {
  Jacobian6 J;
  forward(q, &J);
  J.bottomRows<3>() *= rotation_weight;
  // σ_min(J) = sqrt(λ_min(JᵀJ)).
  const Eigen::SelfAdjointEigenSolver<Jacobian6> eig(J.transpose() * J, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(0.0, eig.eigenvalues()[0]));
}

IkResult Xarm6Kinematics::inverse(const Eigen::Isometry3d& T_robot_flange_target,
                                  const JointVector& q_seed, const IkOptions& options) const {
  TS_ASSERT(options.max_iterations >= 0 && options.rotation_weight > 0 &&
                options.min_damping > 0 && options.max_step > 0,
            options.max_iterations, options.rotation_weight, options.min_damping,
            options.max_step);
  IkResult result;
  result.q = clampToLimits(q_seed);
  const Eigen::Vector3d p_t = T_robot_flange_target.translation();
  const Eigen::Matrix3d R_t = T_robot_flange_target.linear();
  if (!p_t.allFinite() || !isRotation(R_t, 1e-6)) {
    result.status = IkResult::Status::kInvalidTarget;
    return result;
  }
  const double w = options.rotation_weight;
  const auto evaluate = [&](const JointVector& q, Residual& r) {
    Jacobian6 J;
    const Eigen::Isometry3d T = forward(q, &J);
    const Eigen::Vector3d dp = p_t - T.translation();
    const Eigen::Vector3d dtheta = rotationLog(R_t * T.linear().transpose());
    r.e << dp, w * dtheta;
    r.J_w = J;
    r.J_w.bottomRows<3>() *= w;
    r.cost = r.e.squaredNorm();
    r.position_error = dp.norm();
    r.angle_error = dtheta.norm();
  };

  JointVector q = result.q;
  Residual cur, next;
  evaluate(q, cur);
  double lambda = std::max(options.min_damping, 1e-2);
  constexpr double kMaxDamping = 1e3;
  bool converged = false;
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    if (cur.position_error <= options.position_tolerance &&
        cur.angle_error <= options.angle_tolerance) {
      converged = true;
      break;
    }
    // Damped least squares with an active set: a joint on its limit whose step points outwards
    // is held, and the step is solved again for the others (projected Levenberg–Marquardt).
    Jacobian6 J_free = cur.J_w;
    Vector6 dq = Vector6::Zero();
    for (int pass = 0; pass < 3; ++pass) {
      Matrix6 A = J_free.transpose() * J_free;
      A.diagonal().array() += lambda * lambda;
      dq = A.ldlt().solve(J_free.transpose() * cur.e);
      bool changed = false;
      for (int i = 0; i < kDof; ++i) {
        const bool blocked = (q[i] <= lower_[i] && dq[i] < 0) || (q[i] >= upper_[i] && dq[i] > 0);
        if (blocked && !J_free.col(i).isZero(0)) {
          J_free.col(i).setZero();
          changed = true;
        }
        if (J_free.col(i).isZero(0)) dq[i] = 0;
      }
      if (!changed) break;
    }
    const double biggest = dq.cwiseAbs().maxCoeff();
    if (biggest > options.max_step) dq *= options.max_step / biggest;
    const JointVector q_next = clampToLimits(q + dq);
    evaluate(q_next, next);
    if (next.cost < cur.cost) {
      const double gain = cur.cost - next.cost;
      const double step = (q_next - q).norm();
      q = q_next;
      std::swap(cur, next);
      lambda = std::max(options.min_damping, lambda * 0.3);
      // Stalled at a local optimum (unreachable target): progress too small to matter.
      if (step < 1e-9 || gain <= 1e-15 * (1.0 + cur.cost)) break;
    } else {
      lambda *= 5.0;
      if (lambda > kMaxDamping) break;
    }
  }
  result.q = q;
  result.iterations = it;
  result.position_error = cur.position_error;
  result.angle_error = cur.angle_error;
  result.status = converged ? IkResult::Status::kConverged : IkResult::Status::kClosestReachable;
  if (!converged && cur.position_error <= options.position_tolerance &&
      cur.angle_error <= options.angle_tolerance)
    result.status = IkResult::Status::kConverged;
  for (int i = 0; i < kDof; ++i) {
    if (q[i] <= lower_[i] || q[i] >= upper_[i]) result.at_joint_limit = true;
  }
  TS_ASSERT(withinLimits(result.q), result.q.transpose());
  return result;
}

}  // namespace telesphere::robot::arm
