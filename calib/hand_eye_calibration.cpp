// SPDX-License-Identifier: MIT
/// @brief Hand-eye calibration (see hand_eye_calibration.h).
#include "calib/hand_eye_calibration.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "calib/bearing_pose.h"
#include "calib/calibration_problem.h"

namespace telesphere::calib {

std::array<Eigen::Vector3d, 4> markerCorners(double marker_size) {
  const double h = 0.5 * marker_size;
  return {Eigen::Vector3d(-h, h, 0), Eigen::Vector3d(h, h, 0), Eigen::Vector3d(h, -h, 0),
          Eigen::Vector3d(-h, -h, 0)};
}

namespace {

constexpr double kDeg = M_PI / 180.0;

/// Spread of the axes of the relative rotations R_iᵀ·R_j (deg), see HandEyeIdentifiability.
double axisSpreadDeg(const std::vector<Eigen::Matrix3d>& rotations, double min_rotation_deg) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  const std::size_t n = rotations.size();
  const std::size_t stride = std::max<std::size_t>(1, n / 64);
  int count = 0;
  for (std::size_t i = 0; i < n; i += stride) {
    for (std::size_t j = i + 1; j < n; j += stride) {
      const Eigen::AngleAxisd aa(rotations[i].transpose() * rotations[j]);
      if (aa.angle() < min_rotation_deg * kDeg) continue;
      scatter += aa.axis() * aa.axis().transpose();
      ++count;
    }
  }
  if (count < 2) return 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const double l1 = eig.eigenvalues()[2], l2 = std::max(0.0, eig.eigenvalues()[1]);
  return std::atan(std::sqrt(l2 / l1)) / kDeg;
}

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) *= -1;
  return U * svd.matrixV().transpose();
}

Eigen::MatrixXd kron(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  Eigen::MatrixXd K(A.rows() * B.rows(), A.cols() * B.cols());
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      K.block(i * B.rows(), j * B.cols(), B.rows(), B.cols()) = A(i, j) * B;
  return K;
}

/// Closed-form F_i·X·M_i = Z·W_i·Y for {X, Z, Y}; nothing when degenerate.
std::optional<std::array<Eigen::Isometry3d, 3>> solveAXBYCZ(
    const std::vector<Eigen::Isometry3d>& F, const std::vector<Eigen::Isometry3d>& M,
    const std::vector<Eigen::Isometry3d>& W) {
  const std::size_t n = F.size();
  Eigen::MatrixXd A(9 * n, 90);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d RW = W[i].linear();
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> w(RW.data());
    A.block(9 * i, 0, 9, 9) = kron(M[i].linear().transpose(), F[i].linear());
    A.block(9 * i, 9, 9, 81) = -kron(w.transpose(), Eigen::MatrixXd::Identity(9, 9));
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinV);
  const Eigen::VectorXd u = svd.matrixV().col(89);
  Eigen::Matrix3d RX = Eigen::Map<const Eigen::Matrix3d>(u.data());
  const double det = RX.determinant();
  if (!(std::abs(det) > 1e-12)) return std::nullopt;
  const double lambda = std::cbrt(det);
  RX /= lambda;
  const Eigen::Matrix<double, 9, 9> K = Eigen::Map<const Eigen::Matrix<double, 9, 9>>(u.data() + 9) / lambda;
  // K = R_Yᵀ ⊗ R_Z: rearranged, Q((i,j),(k,l)) = R_Yᵀ(i,j)·R_Z(k,l) is rank one.
  Eigen::Matrix<double, 9, 9> Q;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) Q(i * 3 + j, k * 3 + l) = K(i * 3 + k, j * 3 + l);
  const Eigen::JacobiSVD<Eigen::Matrix<double, 9, 9>> qsvd(Q, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const double s = std::sqrt(qsvd.singularValues()[0]);
  Eigen::Matrix3d RYt, RZ;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      RYt(i, j) = s * qsvd.matrixU()(i * 3 + j, 0);
      RZ(i, j) = s * qsvd.matrixV()(i * 3 + j, 0);
    }
  if (RYt.determinant() < 0) {
    RYt = -RYt;
    RZ = -RZ;
  }
  std::array<Eigen::Isometry3d, 3> out;
  for (auto& T : out) T = Eigen::Isometry3d::Identity();
  out[0].linear() = nearestRotation(RX);
  out[1].linear() = nearestRotation(RZ);
  out[2].linear() = nearestRotation(RYt.transpose());
  // Translations: R_F·t_X − R_Z·R_W·t_Y − t_Z = R_Z·t_W − t_F − R_F·R_X·t_M.
  Eigen::MatrixXd B(3 * n, 9);
  Eigen::VectorXd b(3 * n);
  const Eigen::Matrix3d& R_X = out[0].linear();
  const Eigen::Matrix3d& R_Z = out[1].linear();
  for (std::size_t i = 0; i < n; ++i) {
    B.block<3, 3>(3 * i, 0) = F[i].linear();
    B.block<3, 3>(3 * i, 3) = -R_Z * W[i].linear();
    B.block<3, 3>(3 * i, 6) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * i) = R_Z * W[i].translation() - F[i].translation() -
                          F[i].linear() * R_X * M[i].translation();
  }
  const Eigen::VectorXd t = B.colPivHouseholderQr().solve(b);
  out[0].translation() = t.segment<3>(0);
  out[2].translation() = t.segment<3>(3);
  out[1].translation() = t.segment<3>(6);
  for (const auto& T : out)
    if (!T.matrix().allFinite()) return std::nullopt;
  return out;
}

/// With X known: P_i = F_i·X·M_i = Z·W_i·Y (the marker in the robot frame). Relative motions
/// give A·Z = Z·B (A = P_j·P_i⁻¹, B = W_j·W_i⁻¹): R_Z aligns the rotation axes of B with those of
/// A (orthogonal Procrustes), t_Z from (R_A − I)·t_Z = R_Z·t_B − t_A; then Y = W_i⁻¹·Z⁻¹·P_i
/// averaged. Nothing when fewer than two relative rotations carry an axis.
std::optional<std::array<Eigen::Isometry3d, 3>> solveWithKnownX(const std::vector<Eigen::Isometry3d>& F,
                                                                const std::vector<Eigen::Isometry3d>& M,
                                                                const std::vector<Eigen::Isometry3d>& W,
                                                                const Eigen::Isometry3d& X, double min_rotation_deg) {
  const std::size_t n = F.size();
  std::vector<Eigen::Isometry3d> P(n);
  for (std::size_t i = 0; i < n; ++i) P[i] = F[i] * X * M[i];
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  std::vector<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> motions;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const Eigen::Isometry3d A = P[j] * P[i].inverse(), B = W[j] * W[i].inverse();
      const Eigen::AngleAxisd a(A.linear()), b(B.linear());
      if (b.angle() < min_rotation_deg * M_PI / 180.0) continue;
      H += (b.axis() * b.angle()) * (a.axis() * a.angle()).transpose();
      motions.emplace_back(A, B);
    }
  if (motions.size() < 2) return std::nullopt;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R_Z = svd.matrixV() * D * svd.matrixU().transpose();
  Eigen::MatrixXd C(3 * motions.size(), 3);
  Eigen::VectorXd c(3 * motions.size());
  for (std::size_t k = 0; k < motions.size(); ++k) {
    const auto& [A, B] = motions[k];
    C.block<3, 3>(3 * Eigen::Index(k), 0) = A.linear() - Eigen::Matrix3d::Identity();
    c.segment<3>(3 * Eigen::Index(k)) = R_Z * B.translation() - A.translation();
  }
  std::array<Eigen::Isometry3d, 3> out;
  out[0] = X;
  out[1] = Eigen::Isometry3d::Identity();
  out[1].linear() = R_Z;
  out[1].translation() = C.colPivHouseholderQr().solve(c);
  Eigen::Matrix3d R_sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d t_sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Isometry3d Y_i = W[i].inverse() * out[1].inverse() * P[i];
    R_sum += Y_i.linear();
    t_sum += Y_i.translation();
  }
  out[2] = Eigen::Isometry3d::Identity();
  out[2].linear() = nearestRotation(R_sum);
  out[2].translation() = t_sum / double(n);
  for (const auto& T : out)
    if (!T.matrix().allFinite()) return std::nullopt;
  return out;
}

/// Reprojection of one marker corner of one sample into cam_l (T_cam_cam_l = identity) or cam_r.
template <typename ModelD>
struct MarkerCornerCost {
  const ModelD* camera;
  Eigen::Isometry3d T_flange_robot;  ///< T_robot_flange(i)⁻¹
  Eigen::Isometry3d T_mount_wrist;
  Eigen::Isometry3d T_cam_cam_l;
  Eigen::Vector3d p_marker;
  Eigen::Vector2d observed_px;

  template <typename T>
  bool operator()(const T* q_fc, const T* t_fc, const T* q_rm, const T* t_rm, const T* q_wm,
                  const T* t_wm, T* r) const {
    using Cam = decltype(std::declval<const ModelD&>().template cast<T>());
    typename Cam::Params params = camera->params().template cast<T>();
    const Cam& cam = detail::cachedCamera<Cam>(params.data());
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Vec3 p_wrist = detail::transformPoint(q_wm, t_wm, p_marker.cast<T>().eval());
    const Vec3 p_mount = T_mount_wrist.cast<T>() * p_wrist;
    const Vec3 p_robot = detail::transformPoint(q_rm, t_rm, p_mount);
    const Vec3 p_flange = T_flange_robot.cast<T>() * p_robot;
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_fc);
    const Vec3 p_cam_l = q.conjugate() * (p_flange - Eigen::Map<const Vec3>(t_fc));
    const Vec3 p_cam = T_cam_cam_l.cast<T>() * p_cam_l;
    return detail::reprojectionResidual(cam, p_cam, observed_px, r);
  }
};

/// What a refinement of the three poses works on.
struct HandEyeFitInput {
  const SystemCalibration* cameras;
  bool stereo;
  const std::vector<const HandEyeSample*>* used;
  const std::array<Eigen::Vector3d, 4>* corners3;
};

/// Adds one residual block per marker corner seen in either camera; the count of corners.
int addMarkerResiduals(const HandEyeFitInput& in, double huber_px, detail::PoseBlock& X, detail::PoseBlock& Z,
                       detail::PoseBlock& Y, ceres::Problem& problem) {
  int corners = 0;
  for (const HandEyeSample* s : *in.used) {
    for (int c = 0; c < (in.stereo ? 2 : 1); ++c) {
      const auto& obs = c == 0 ? s->corners_l : s->corners_r;
      if (!obs) continue;
      const Eigen::Isometry3d T_cam_cam_l =
          c == 0 ? Eigen::Isometry3d::Identity() : in.cameras->T_cam_l_cam_r->inverse();
      in.cameras->cameras[static_cast<std::size_t>(c)].camera.visit([&](const auto& model) {
        using ModelD = std::decay_t<decltype(model)>;
        for (int k = 0; k < 4; ++k) {
          auto* cost = new ceres::AutoDiffCostFunction<MarkerCornerCost<ModelD>, 2, 4, 3, 4, 3, 4, 3>(
              new MarkerCornerCost<ModelD>{&model, s->T_robot_flange.inverse(), s->T_mount_wrist,
                                           T_cam_cam_l, (*in.corners3)[static_cast<std::size_t>(k)],
                                           (*obs)[static_cast<std::size_t>(k)]});
          problem.AddResidualBlock(cost, new ceres::HuberLoss(huber_px), X.q.data(), X.t.data(), Z.q.data(),
                                   Z.t.data(), Y.q.data(), Y.t.data());
          ++corners;
        }
      });
    }
  }
  return corners;
}

/// The robust cost of the three poses {X, Z, Y} without solving (to rank starts).
double handEyeCost(const HandEyeFitInput& in, const std::array<Eigen::Isometry3d, 3>& poses) {
  detail::PoseBlock X = detail::PoseBlock::from(poses[0]), Z = detail::PoseBlock::from(poses[1]),
                    Y = detail::PoseBlock::from(poses[2]);
  ceres::Problem problem;
  X.addTo(problem);
  Z.addTo(problem);
  Y.addTo(problem);
  addMarkerResiduals(in, HandEyeOptions{}.huber_px, X, Z, Y, problem);
  double cost = INFINITY;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions{}, &cost, nullptr, nullptr, nullptr) || !std::isfinite(cost))
    return INFINITY;
  return cost;
}

/// Refines {X, Z, Y} from `start` with Ceres and fills r's poses, costs, standard deviations and
/// per-camera and per-sample fits (indices into `used`); the median per-sample RMS (px).
SolveResult<double> refineHandEye(const HandEyeFitInput& in, const std::array<Eigen::Isometry3d, 3>& start,
                                  const HandEyeOptions& options, HandEyeResult& r) {
  detail::PoseBlock X = detail::PoseBlock::from(start[0]);
  detail::PoseBlock Z = detail::PoseBlock::from(start[1]);
  detail::PoseBlock Y = detail::PoseBlock::from(start[2]);
  ceres::Problem problem;
  X.addTo(problem);
  Z.addTo(problem);
  Y.addTo(problem);
  const int corners = addMarkerResiduals(in, options.huber_px, X, Z, Y, problem);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = 1e-12;
  so.parameter_tolerance = 1e-12;
  detail::ProgressCallback callback("hand-eye", options.progress, corners);
  so.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
    return CalibrationFailure{CalibrationError::kDiverged, "the hand-eye solve failed: " + summary.message};
  r.initial_cost = summary.initial_cost;
  r.final_cost = summary.final_cost;
  r.T_flange_cam_l = X.toIsometry();
  r.T_robot_mount = Z.toIsometry();
  r.T_wrist_marker = Y.toIsometry();

  // Standard deviations: the covariance of the three poses, scaled by the residuals' variance.
  // The quaternion manifold's tangent δ rotates by 2|δ| (Ceres: q' = [cos|δ|, sin|δ|·δ/|δ|]·q).
  {
    ceres::Covariance covariance(ceres::Covariance::Options{});
    std::vector<std::pair<const double*, const double*>> blocks;
    for (detail::PoseBlock* b : {&X, &Z, &Y}) {
      blocks.emplace_back(b->q.data(), b->q.data());
      blocks.emplace_back(b->t.data(), b->t.data());
    }
    if (covariance.Compute(blocks, &problem)) {
      const double dof = std::max(1, 2 * corners - 18);
      const double sigma2 = 2.0 * summary.final_cost / dof;
      int k = 0;
      for (detail::PoseBlock* b : {&X, &Z, &Y}) {
        Eigen::Matrix3d cov_r, cov_t;
        PoseStddev& sd = r.stddev[static_cast<std::size_t>(k++)];
        sd = PoseStddev{};
        if (!covariance.GetCovarianceBlockInTangentSpace(b->q.data(), b->q.data(), cov_r.data()) ||
            !covariance.GetCovarianceBlock(b->t.data(), b->t.data(), cov_t.data()))
          continue;
        PoseCovariance cov = PoseCovariance::Zero();  // (θ = 2δ, t); only the diagonal blocks are read
        cov.topLeftCorner<3, 3>() = 4.0 * cov_r * sigma2;
        cov.bottomRightCorner<3, 3>() = cov_t * sigma2;
        sd = poseStddev(cov);  // a NaN variance leaves it not valid (std::max(0.0, NaN) was 0)
      }
    }
  }

  // Final errors per camera and per sample. A corner the model cannot project counts as
  // unfitted: the solve gave it no residual, so a start that put the marker behind a camera
  // must not look like a good fit.
  const std::vector<const HandEyeSample*>& used = *in.used;
  r.sample_fits.assign(used.size(), HandEyeSampleFit{});
  std::vector<double> sample_sum2(used.size(), 0.0);
  std::vector<int> unprojected(used.size(), 0);
  for (int c = 0; c < (in.stereo ? 2 : 1); ++c) {
    double sum2 = 0;
    int n = 0;
    const Eigen::Isometry3d T_cam_cam_l =
        c == 0 ? Eigen::Isometry3d::Identity() : in.cameras->T_cam_l_cam_r->inverse();
    for (std::size_t i = 0; i < used.size(); ++i) {
      const HandEyeSample* s = used[i];
      const auto& obs = c == 0 ? s->corners_l : s->corners_r;
      if (!obs) continue;
      const Eigen::Isometry3d T_cam_marker = T_cam_cam_l * r.T_flange_cam_l.inverse() *
                                             s->T_robot_flange.inverse() * r.T_robot_mount *
                                             s->T_mount_wrist * r.T_wrist_marker;
      for (std::size_t k = 0; k < 4; ++k) {
        Eigen::Vector2d px;
        if (!in.cameras->cameras[static_cast<std::size_t>(c)].camera.project(T_cam_marker * (*in.corners3)[k], px)) {
          ++unprojected[i];
          continue;
        }
        const double e2 = (px - (*obs)[k]).squaredNorm();
        sum2 += e2;
        sample_sum2[i] += e2;
        ++r.sample_fits[i].corners;
        ++n;
      }
    }
    (c == 0 ? r.rms_px_l : r.rms_px_r) = n ? std::sqrt(sum2 / n) : 0.0;
  }
  std::vector<double> sample_rms;
  for (std::size_t i = 0; i < used.size(); ++i) {
    HandEyeSampleFit& fit = r.sample_fits[i];
    fit.rms_px = fit.corners ? std::sqrt(sample_sum2[i] / fit.corners) : 0.0;
    sample_rms.push_back(unprojected[i] > 0 ? INFINITY : fit.rms_px);
  }
  std::nth_element(sample_rms.begin(), sample_rms.begin() + std::ptrdiff_t(sample_rms.size() / 2), sample_rms.end());
  return sample_rms[sample_rms.size() / 2];
}

}  // namespace

HandEyeIdentifiability checkHandEyeIdentifiability(const std::vector<HandEyeSample>& samples,
                                                   const HandEyeOptions& options) {
  HandEyeIdentifiability out;
  std::vector<Eigen::Matrix3d> head, wrist;
  for (const auto& s : samples) {
    if (!s.corners_l && !s.corners_r) continue;
    head.push_back(s.T_robot_flange.linear());
    wrist.push_back(s.T_mount_wrist.linear());
  }
  out.samples = static_cast<int>(head.size());
  out.head_axis_spread_deg = axisSpreadDeg(head, options.min_rotation_deg);
  out.wrist_axis_spread_deg = axisSpreadDeg(wrist, options.min_rotation_deg);
  char buf[320];
  if (out.samples < options.min_samples) {
    std::snprintf(buf, sizeof buf, "only %d samples show the marker, at least %d needed",
                  out.samples, options.min_samples);
    out.message = buf;
  } else if (out.head_axis_spread_deg < options.min_axis_spread_deg) {
    std::snprintf(buf, sizeof buf,
                  "the head arm's rotations do not separate the unknowns: their axes spread only "
                  "%.1f deg (need %.1f); rotate the head about at least two non-parallel axes",
                  out.head_axis_spread_deg, options.min_axis_spread_deg);
    out.message = buf;
  } else if (out.wrist_axis_spread_deg < options.min_axis_spread_deg) {
    std::snprintf(buf, sizeof buf,
                  "the manipulator's wrist rotations do not separate the unknowns: their axes "
                  "spread only %.1f deg (need %.1f); rotate the wrist about at least two "
                  "non-parallel axes",
                  out.wrist_axis_spread_deg, options.min_axis_spread_deg);
    out.message = buf;
  } else {
    out.ok = true;
  }
  return out;
}

SolveResult<HandEyeResult> calibrateHandEye(const SystemCalibration& cameras, double marker_size,
                                            const std::vector<HandEyeSample>& samples,
                                            const HandEyeOptions& options) {
  const auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  if (cameras.cameras.empty())
    return CalibrationFailure{CalibrationError::kInitialisationFailed,
                              "hand-eye calibration needs calibrated camera intrinsics"};
  const bool stereo = cameras.cameras.size() == 2 && cameras.T_cam_l_cam_r.has_value();
  HandEyeResult result;
  result.identifiability = checkHandEyeIdentifiability(samples, options);
  if (result.identifiability.samples < options.min_samples)
    return CalibrationFailure{CalibrationError::kTooFewViews, result.identifiability.message};
  if (!result.identifiability.ok)
    return CalibrationFailure{CalibrationError::kNotIdentifiable, result.identifiability.message};

  // Marker pose per sample from bearings (cam_l, else cam_r through T_cam_l_cam_r).
  const auto corners3 = markerCorners(marker_size);
  const std::vector<Eigen::Vector3d> p_marker(corners3.begin(), corners3.end());
  std::vector<Eigen::Isometry3d> F, M, W;
  std::vector<const HandEyeSample*> used;
  std::vector<std::size_t> used_index;
  for (const auto& s : samples) {
    std::optional<Eigen::Isometry3d> T_cam_l_marker;
    for (int c = 0; c < (stereo ? 2 : 1) && !T_cam_l_marker; ++c) {
      const auto& corners = c == 0 ? s.corners_l : s.corners_r;
      if (!corners) continue;
      std::vector<Eigen::Vector3d> d;
      for (const auto& px : *corners) {
        Eigen::Vector3d ray;
        if (cameras.cameras[static_cast<std::size_t>(c)].camera.unproject(px, ray)) d.push_back(ray);
      }
      if (d.size() != 4) continue;
      const auto pose = planarPoseFromBearings(p_marker, d);
      if (pose) T_cam_l_marker = c == 0 ? *pose : *cameras.T_cam_l_cam_r * *pose;
    }
    if (!T_cam_l_marker) continue;
    F.push_back(s.T_robot_flange);
    M.push_back(*T_cam_l_marker);
    W.push_back(s.T_mount_wrist);
    used.push_back(&s);
    used_index.push_back(static_cast<std::size_t>(&s - samples.data()));
  }
  if (static_cast<int>(used.size()) < options.min_samples)
    return CalibrationFailure{CalibrationError::kTooFewViews,
                              "the marker pose could be found in only " + std::to_string(used.size()) +
                                  " samples, at least " + std::to_string(options.min_samples) + " needed"};
  // Starts: the closed form (from kClosedFormMinSamples samples) and the given T_flange_cam_l.
  // Either can lead Ceres into a wrong minimum (the closed form is noisy with few samples, the
  // guess is the calibration being corrected), so the one with the lower cost is refined first
  // and the other as well when the first does not fit the samples; the better fit is kept.
  struct Start {
    const char* name;
    std::array<Eigen::Isometry3d, 3> poses;
    double cost = 0;
  };
  std::vector<Start> starts;
  if (static_cast<int>(used.size()) >= kClosedFormMinSamples) {
    progress("hand-eye: closed-form initialisation from " + std::to_string(used.size()) + " samples");
    if (auto closed = solveAXBYCZ(F, M, W)) starts.push_back({"closed form", *closed});
  }
  if (options.T_flange_cam_l_guess) {
    if (auto known = solveWithKnownX(F, M, W, *options.T_flange_cam_l_guess, options.min_rotation_deg))
      starts.push_back({"the given T_flange_cam_l", *known});
  }
  if (starts.empty()) {
    if (static_cast<int>(used.size()) < kClosedFormMinSamples)
      return CalibrationFailure{CalibrationError::kTooFewViews,
                                "the closed-form hand-eye initialisation needs " +
                                    std::to_string(kClosedFormMinSamples) + " samples (have " +
                                    std::to_string(used.size()) + ") or a starting T_flange_cam_l"};
    return CalibrationFailure{CalibrationError::kInitialisationFailed,
                              "the closed-form hand-eye initialisation is degenerate"};
  }
  const HandEyeFitInput input{&cameras, stereo, &used, &corners3};
  for (Start& s : starts) s.cost = handEyeCost(input, s.poses);
  std::stable_sort(starts.begin(), starts.end(), [](const Start& a, const Start& b) { return a.cost < b.cost; });

  std::optional<HandEyeResult> best;
  double best_median_rms = INFINITY;
  for (const Start& start : starts) {
    progress(std::string("hand-eye: refining from ") + start.name);
    HandEyeResult r = result;
    const auto refined = refineHandEye(input, start.poses, options, r);
    if (!refined) {
      if (!best && &start == &starts.back()) return refined.failure();
      continue;
    }
    r.initial = start.poses;
    r.samples_used = static_cast<int>(used.size());
    for (std::size_t i = 0; i < used.size(); ++i) r.sample_fits[i].index = used_index[i];
    const double median_rms = *refined;
    if (!best || r.final_cost < best->final_cost) {
      best = std::move(r);
      best_median_rms = median_rms;
    }
    if (best_median_rms <= options.max_rms_px) break;
  }
  // Diverged when the typical sample does not fit: the median of the per-sample RMS, not the
  // overall RMS, which one gross outlier (a still whose image and joints disagree) inflates
  // past any bound for every later solve, so that it could never be marked and removed.
  if (!(best_median_rms <= options.max_rms_px))
    return CalibrationFailure{CalibrationError::kDiverged,
                              "the hand-eye solve diverged: the median sample RMS " + std::to_string(best_median_rms) +
                                  " px exceeds " + std::to_string(options.max_rms_px) +
                                  " px (wrong marker size, intrinsics or kinematics?)"};
  return *best;
}

}  // namespace telesphere::calib
