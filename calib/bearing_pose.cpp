// SPDX-License-Identifier: MIT
/// @brief Planar target pose from bearing vectors (see bearing_pose.h).
#include "calib/bearing_pose.h"

#include <Eigen/SVD>
#include <cmath>

namespace telesphere::calib {

std::optional<Eigen::Isometry3d> planarPoseFromBearings(const std::vector<Eigen::Vector3d>& p_target,
                                                        const std::vector<Eigen::Vector3d>& d_cam) {
  const std::size_t n = p_target.size();
  if (n < 4 || d_cam.size() != n) return std::nullopt;
  // Normalise the plane coordinates (centroid at 0, mean distance √2) for conditioning.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : p_target) mean += p.head<2>();
  mean /= double(n);
  double spread = 0;
  for (const auto& p : p_target) spread += (p.head<2>() - mean).norm();
  spread /= double(n);
  if (!(spread > 0)) return std::nullopt;
  const double s = std::sqrt(2.0) / spread;
  Eigen::Matrix3d N;
  N << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;

  Eigen::MatrixXd A(3 * n, 9);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = N * Eigen::Vector3d(p_target[i].x(), p_target[i].y(), 1.0);
    const Eigen::Vector3d& d = d_cam[i];
    const Eigen::RowVector3d qt = q.transpose();
    const Eigen::RowVector3d z = Eigen::RowVector3d::Zero();
    // Rows of d × (H q) = 0 with h = (row 1, row 2, row 3 of H).
    A.row(3 * i) << z, -d.z() * qt, d.y() * qt;
    A.row(3 * i + 1) << d.z() * qt, z, -d.x() * qt;
    A.row(3 * i + 2) << -d.y() * qt, d.x() * qt, z;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d H;
  H << h.segment<3>(0).transpose(), h.segment<3>(3).transpose(), h.segment<3>(6).transpose();
  H = H * N;
  // H = λ·[r1 r2 t]: the sign makes the rays point at the target points, not away.
  double agree = 0;
  for (std::size_t i = 0; i < n; ++i)
    agree += d_cam[i].dot(H * Eigen::Vector3d(p_target[i].x(), p_target[i].y(), 1.0));
  const double norm = 0.5 * (H.col(0).norm() + H.col(1).norm());
  if (!(norm > 0) || !std::isfinite(norm)) return std::nullopt;
  H /= (agree < 0 ? -norm : norm);
  Eigen::Matrix3d R;
  R.col(0) = H.col(0);
  R.col(1) = H.col(1);
  R.col(2) = H.col(0).cross(H.col(1));
  const Eigen::JacobiSVD<Eigen::Matrix3d> rsvd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = rsvd.matrixU();
  if ((U * rsvd.matrixV().transpose()).determinant() < 0) U.col(2) *= -1;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = U * rsvd.matrixV().transpose();
  T.translation() = H.col(2);
  if (!T.matrix().allFinite()) return std::nullopt;
  return T;
}

}  // namespace telesphere::calib
