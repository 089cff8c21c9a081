// SPDX-License-Identifier: MIT
/// @brief Intrinsic and stereo calibration by Ceres (see intrinsic_calibration.h).
#include "calib/intrinsic_calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include <Eigen/LU>

#include "calib/bearing_pose.h"
#include "calib/calibration_problem.h"

namespace telesphere::calib {

Eigen::VectorXd defaultParams(const std::string& model, double f, int width, int height) {
  const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  Eigen::VectorXd p;
  if (model == "ds") {
    p.resize(6);
    p << f, f, cx, cy, 0.0, 0.5;
  } else if (model == "eucm") {
    p.resize(6);
    p << f, f, cx, cy, 0.5, 1.0;
  } else {
    p.resize(8);
    p << f, f, cx, cy, 0, 0, 0, 0;
  }
  return p;
}

bool IntrinsicResult::degenerate() const {
  return std::any_of(cameras.begin(), cameras.end(),
                     [](const CameraIntrinsicResult& c) { return !c.degeneracy_warning.empty(); });
}

SystemCalibration IntrinsicResult::toSystemCalibration() const {
  SystemCalibration out;
  for (const auto& c : cameras) out.cameras.push_back(c.calibration);
  out.T_cam_l_cam_r = T_cam_l_cam_r;
  return out;
}

namespace {

/// Runs f(model) with a Model<double> instance of the named model (for its type).
template <typename F>
void withIntrinsicModel(const std::string& model, F&& f) {
  const auto camera = GenericCamera::create(model, defaultParams(model, 100.0, 100, 100));
  camera->visit([&](const auto& m) { f(m); });
}

template <typename ModelD>
struct BoardCornerCost {
  Eigen::Vector3d p_board;
  Eigen::Vector2d observed_px;

  template <typename T>
  bool operator()(const T* intrinsics, const T* q_cam_board, const T* t_cam_board, T* r) const {
    using Cam = decltype(std::declval<const ModelD&>().template cast<T>());
    const Cam& cam = detail::cachedCamera<Cam>(intrinsics);
    const Eigen::Matrix<T, 3, 1> p_cam =
        detail::transformPoint(q_cam_board, t_cam_board, p_board.cast<T>().eval());
    return detail::reprojectionResidual(cam, p_cam, observed_px, r);
  }
};

/// The right camera's corner: p_cam_r = T_cam_r_cam_l · T_cam_l_board · p_board.
template <typename ModelD>
struct StereoCornerCost {
  Eigen::Vector3d p_board;
  Eigen::Vector2d observed_px;

  template <typename T>
  bool operator()(const T* intrinsics, const T* q_l_b, const T* t_l_b, const T* q_r_l,
                  const T* t_r_l, T* r) const {
    using Cam = decltype(std::declval<const ModelD&>().template cast<T>());
    const Cam& cam = detail::cachedCamera<Cam>(intrinsics);
    const Eigen::Matrix<T, 3, 1> p_cam_l =
        detail::transformPoint(q_l_b, t_l_b, p_board.cast<T>().eval());
    const Eigen::Matrix<T, 3, 1> p_cam_r = detail::transformPoint(q_r_l, t_r_l, p_cam_l);
    return detail::reprojectionResidual(cam, p_cam_r, observed_px, r);
  }
};

double medianOf(std::vector<double> v) {
  if (v.empty()) return INFINITY;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// Pose of the board in one view from the bearings of its corners through `camera`.
std::optional<Eigen::Isometry3d> viewPose(const GenericCamera& camera, const AprilGrid& target,
                                          const TargetObservation& obs) {
  std::vector<Eigen::Vector3d> p_board, d_cam;
  for (std::size_t i = 0; i < obs.corner_ids.size(); ++i) {
    Eigen::Vector3d d;
    if (!camera.unproject(obs.corners_px[i], d)) continue;
    p_board.push_back(target.cornerPosition(obs.corner_ids[i]));
    d_cam.push_back(d);
  }
  return planarPoseFromBearings(p_board, d_cam);
}

/// Median reprojection error of one view after a pose from bearings (image size when unusable).
double viewInitError(const GenericCamera& camera, const AprilGrid& target,
                     const TargetObservation& obs, double penalty) {
  const auto pose = viewPose(camera, target, obs);
  if (!pose) return penalty;
  std::vector<double> errors;
  for (std::size_t i = 0; i < obs.corner_ids.size(); ++i) {
    Eigen::Vector2d px;
    errors.push_back(camera.project(*pose * target.cornerPosition(obs.corner_ids[i]), px)
                         ? (px - obs.corners_px[i]).norm()
                         : penalty);
  }
  return medianOf(errors);
}

/// Focal length search: the default parameters of the model at each focal length, scored by
/// the median over (up to 12) views of the median reprojection error after poses from bearings.
Eigen::VectorXd initialIntrinsics(const CameraViews& cam, const AprilGrid& target,
                                  const std::vector<int>& usable) {
  std::vector<int> sample;
  const std::size_t step = std::max<std::size_t>(1, usable.size() / 12);
  for (std::size_t i = 0; i < usable.size() && sample.size() < 12; i += step) sample.push_back(usable[i]);
  const double size = std::max(cam.width, cam.height);
  const auto score = [&](double f) {
    const auto camera = GenericCamera::create(cam.model, defaultParams(cam.model, f, cam.width, cam.height));
    if (!camera) return double(INFINITY);
    std::vector<double> per_view;
    for (int v : sample)
      per_view.push_back(viewInitError(*camera, target, cam.views[static_cast<std::size_t>(v)], size));
    return medianOf(per_view);
  };
  double best_f = size, best = INFINITY;
  constexpr int kCoarse = 48;
  const double ratio = std::pow(60.0, 1.0 / (kCoarse - 1));
  for (int k = 0; k < kCoarse; ++k) {
    const double f = 0.05 * size * std::pow(ratio, k);
    const double s = score(f);
    if (s < best) best = s, best_f = f;
  }
  const double centre = best_f;
  for (int k = -5; k <= 5; ++k) {
    const double f = centre * std::pow(ratio, k / 5.0);
    const double s = score(f);
    if (s < best) best = s, best_f = f;
  }
  return defaultParams(cam.model, best_f, cam.width, cam.height);
}

struct CameraState {
  const CameraViews* input = nullptr;
  std::vector<double> params;
  std::vector<int> usable;                               ///< view indices with enough corners
  std::map<int, detail::PoseBlock> T_cam_board;          ///< mono solve: this camera's poses
};

ceres::Solver::Options solverOptions(const IntrinsicOptions& options) {
  ceres::Solver::Options s;
  s.linear_solver_type = ceres::DENSE_SCHUR;
  s.max_num_iterations = options.max_iterations;
  s.num_threads = options.num_threads;
  s.function_tolerance = 1e-10;
  s.parameter_tolerance = 1e-10;
  s.gradient_tolerance = 1e-12;
  return s;
}

/// Adds the corners of `obs` for a camera of the type of ModelD; right = through T_cam_r_cam_l.
template <typename ModelD>
int addCorners(ceres::Problem& problem, const AprilGrid& target, const TargetObservation& obs,
               double* intrinsics, detail::PoseBlock& T_l_b, detail::PoseBlock* T_r_l,
               double huber_px) {
  int n = 0;
  for (std::size_t i = 0; i < obs.corner_ids.size(); ++i) {
    const Eigen::Vector3d p = target.cornerPosition(obs.corner_ids[i]);
    if (T_r_l) {
      auto* cost = new ceres::AutoDiffCostFunction<StereoCornerCost<ModelD>, 2, ModelD::kNumParams,
                                                   4, 3, 4, 3>(
          new StereoCornerCost<ModelD>{p, obs.corners_px[i]});
      problem.AddResidualBlock(cost, new ceres::HuberLoss(huber_px), intrinsics, T_l_b.q.data(),
                               T_l_b.t.data(), T_r_l->q.data(), T_r_l->t.data());
    } else {
      auto* cost = new ceres::AutoDiffCostFunction<BoardCornerCost<ModelD>, 2, ModelD::kNumParams, 4, 3>(
          new BoardCornerCost<ModelD>{p, obs.corners_px[i]});
      problem.AddResidualBlock(cost, new ceres::HuberLoss(huber_px), intrinsics, T_l_b.q.data(),
                               T_l_b.t.data());
    }
    ++n;
  }
  return n;
}

int addCameraCorners(ceres::Problem& problem, const AprilGrid& target, const CameraState& cam,
                     const TargetObservation& obs, double* intrinsics, detail::PoseBlock& T_l_b,
                     detail::PoseBlock* T_r_l, double huber_px) {
  int n = 0;
  withIntrinsicModel(cam.input->model, [&](const auto& m) {
    using ModelD = std::decay_t<decltype(m)>;
    n = addCorners<ModelD>(problem, target, obs, intrinsics, T_l_b, T_r_l, huber_px);
  });
  return n;
}

void addIntrinsicsBlock(ceres::Problem& problem, CameraState& cam) {
  problem.AddParameterBlock(cam.params.data(), static_cast<int>(cam.params.size()));
  detail::setBounds(problem, cam.params.data(),
                    detail::paramBounds(cam.input->model, cam.input->width, cam.input->height));
}

void report(const IntrinsicOptions& options, const std::string& line) {
  if (options.progress) options.progress(line);
}

std::string failureSummary(const ceres::Solver::Summary& summary) {
  return summary.message + " (" + std::to_string(summary.iterations.size()) + " iterations)";
}

/// Solves one camera alone: its intrinsics and its own board poses.
std::optional<CalibrationFailure> solveMono(const AprilGrid& target, CameraState& cam,
                                            const IntrinsicOptions& options,
                                            ceres::Solver::Summary& summary) {
  ceres::Problem problem;
  addIntrinsicsBlock(problem, cam);
  int corners = 0;
  for (int v : cam.usable) {
    detail::PoseBlock& pose = cam.T_cam_board.at(v);
    pose.addTo(problem);
    corners += addCameraCorners(problem, target, cam, cam.input->views[static_cast<std::size_t>(v)],
                                cam.params.data(), pose, nullptr, options.huber_px);
  }
  ceres::Solver::Options so = solverOptions(options);
  detail::ProgressCallback callback(cam.input->label + " intrinsics", options.progress, corners);
  so.callbacks.push_back(&callback);
  ceres::Solve(so, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
    return CalibrationFailure{CalibrationError::kDiverged,
                              cam.input->label + ": the intrinsic solve failed: " + failureSummary(summary)};
  return std::nullopt;
}

Eigen::Isometry3d averagePose(const std::vector<Eigen::Isometry3d>& poses) {
  Eigen::Vector4d q_sum = Eigen::Vector4d::Zero();
  Eigen::Vector3d t_sum = Eigen::Vector3d::Zero();
  const Eigen::Quaterniond q0(poses.front().linear());
  for (const auto& T : poses) {
    Eigen::Quaterniond q(T.linear());
    if (q.dot(q0) < 0) q.coeffs() *= -1;
    q_sum += q.coeffs();
    t_sum += T.translation();
  }
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(q_sum.normalized()).toRotationMatrix();
  out.translation() = t_sum / double(poses.size());
  return out;
}

/// Final errors of one camera with the solved parameters and poses.
CameraIntrinsicResult evaluateCamera(const AprilGrid& target, const CameraState& cam,
                                     const std::map<int, detail::PoseBlock>& T_l_b,
                                     const std::optional<Eigen::Isometry3d>& T_cam_cam_l) {
  const Eigen::VectorXd params = Eigen::Map<const Eigen::VectorXd>(cam.params.data(),
                                                                   static_cast<Eigen::Index>(cam.params.size()));
  const auto camera = GenericCamera::create(cam.input->model, params);
  CameraIntrinsicResult out{CameraCalibration{cam.input->label, *camera, cam.input->width, cam.input->height}};
  double sum2 = 0, sum = 0;
  for (int v : cam.usable) {
    const auto it = T_l_b.find(v);
    if (it == T_l_b.end()) continue;
    const Eigen::Isometry3d T_cam_board = (T_cam_cam_l ? *T_cam_cam_l : Eigen::Isometry3d::Identity()) *
                                          it->second.toIsometry();
    const auto& obs = cam.input->views[static_cast<std::size_t>(v)];
    ViewError ve;
    ve.view = v;
    double view_sum2 = 0;
    for (std::size_t i = 0; i < obs.corner_ids.size(); ++i) {
      Eigen::Vector2d px;
      if (!camera->project(T_cam_board * target.cornerPosition(obs.corner_ids[i]), px)) continue;
      const Eigen::Vector2d e = px - obs.corners_px[i];
      out.residuals.push_back({v, obs.corner_ids[i], obs.corners_px[i], e});
      view_sum2 += e.squaredNorm();
      sum += e.norm();
      ++ve.corners;
    }
    sum2 += view_sum2;
    out.corners += ve.corners;
    ve.rms_px = ve.corners ? std::sqrt(view_sum2 / ve.corners) : 0.0;
    out.per_view.push_back(ve);
  }
  out.views_used = static_cast<int>(out.per_view.size());
  out.rms_px = out.corners ? std::sqrt(sum2 / out.corners) : INFINITY;
  out.mean_px = out.corners ? sum / out.corners : INFINITY;
  return out;
}


/// Indices of the distortion parameters of `model` (those that can trade off with focal length).
std::vector<int> intrinsicDistortionIndices(const std::string& model) {
  if (model == "ds" || model == "eucm") return {4, 5};
  return {4, 5, 6, 7};  // kb4 k1..k4, pinhole k1 k2 p1 p2
}

/// Multiple correlation of parameter `focal` with `others` from the correlation matrix C:
/// R² = 1 − 1/(S⁻¹)₀₀ over the sub-matrix S of (focal, others); 1 when S is singular.
double intrinsicMultipleCorrelation(const Eigen::MatrixXd& C, int focal, const std::vector<int>& others) {
  std::vector<int> idx = {focal};
  idx.insert(idx.end(), others.begin(), others.end());
  const auto n = static_cast<Eigen::Index>(idx.size());
  Eigen::MatrixXd S(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) S(i, j) = C(idx[static_cast<std::size_t>(i)], idx[static_cast<std::size_t>(j)]);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
  lu.setThreshold(1e-12);
  if (!lu.isInvertible()) return 1.0;
  const double inv00 = lu.inverse()(0, 0);
  if (!(inv00 >= 1.0)) return 1.0;  // numerically lost: treat as inseparable
  return std::sqrt(std::max(0.0, 1.0 - 1.0 / inv00));
}

/// Sets param_correlation, focal_distortion_correlation and degeneracy_warning of `cam` from the
/// covariance `cov` of its parameters (empty when the covariance was rank deficient).
void intrinsicSeparability(CameraIntrinsicResult& cam, const std::string& model, const Eigen::MatrixXd& cov,
                           const IntrinsicOptions& options) {
  const auto names = GenericCamera::paramNames(model);
  const std::vector<int> distortion = intrinsicDistortionIndices(model);
  std::string distortion_names;
  for (int i : distortion)
    distortion_names.append(distortion_names.empty() ? "" : ", ").append(names[static_cast<std::size_t>(i)]);
  if (cov.size() == 0) {
    cam.degeneracy_warning = cam.calibration.label +
                             ": the parameter covariance is rank deficient: the views do not determine "
                             "all parameters; show the target near the image rim and strongly tilted";
    return;
  }
  const Eigen::VectorXd d = cov.diagonal().cwiseMax(1e-300).cwiseSqrt();
  cam.param_correlation = d.cwiseInverse().asDiagonal() * cov * d.cwiseInverse().asDiagonal();
  const double r_fx = intrinsicMultipleCorrelation(cam.param_correlation, 0, distortion);
  const double r_fy = intrinsicMultipleCorrelation(cam.param_correlation, 1, distortion);
  cam.focal_distortion_correlation = std::max(r_fx, r_fy);
  if (cam.focal_distortion_correlation > options.max_focal_correlation) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.6f (limit %.6f)", cam.focal_distortion_correlation,
                  options.max_focal_correlation);
    cam.degeneracy_warning = cam.calibration.label + ": the views do not separate the focal length from " +
                             distortion_names + " (multiple correlation " + buf +
                             "): a longer focal length with more distortion fits them as well, so fx, "
                             "fy and " + distortion_names +
                             " are unreliable; add views with the target near the image rim and tilted "
                             "by 30-60 deg";
  }
}

/// Standard deviations of T_r_l⁻¹ (T_cam_l_cam_r) from the covariance of T_r_l's blocks scaled by
/// the residuals' variance. EigenQuaternionManifold perturbs q as exp(δ)·q: a turn by θ = 2δ.
PoseStddev inverseStddev(const ceres::Covariance& covariance, detail::PoseBlock& T_r_l, double sigma2) {
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> cov_qq, cov_tt, cov_qt;
  if (!covariance.GetCovarianceBlockInTangentSpace(T_r_l.q.data(), T_r_l.q.data(), cov_qq.data()) ||
      !covariance.GetCovarianceBlock(T_r_l.t.data(), T_r_l.t.data(), cov_tt.data()) ||
      !covariance.GetCovarianceBlockInTangentSpace(T_r_l.q.data(), T_r_l.t.data(), cov_qt.data()))
    return {};
  PoseCovariance cov;  // (θ, t)
  cov << 4.0 * cov_qq, 2.0 * cov_qt, 2.0 * cov_qt.transpose(), cov_tt;
  return poseStddev(inversePoseCovariance(T_r_l.toIsometry(), cov * sigma2));
}

}  // namespace

SolveResult<IntrinsicResult> calibrateIntrinsics(const AprilGrid& target,
                                                 const std::vector<CameraViews>& cameras,
                                                 const IntrinsicOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (cameras.empty() || cameras.size() > 2)
    return CalibrationFailure{CalibrationError::kTooFewViews, "expected one or two cameras"};
  if (cameras.size() == 2 && cameras[0].views.size() != cameras[1].views.size())
    return CalibrationFailure{CalibrationError::kNoCommonViews,
                              "the two cameras have different numbers of views (" +
                                  std::to_string(cameras[0].views.size()) + " and " +
                                  std::to_string(cameras[1].views.size()) + ")"};
  std::vector<CameraState> state(cameras.size());
  ceres::Solver::Summary mono_summary;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    CameraState& cam = state[c];
    cam.input = &cameras[c];
    if (!GenericCamera::create(cameras[c].model, defaultParams(cameras[c].model, 100, 100, 100)))
      return CalibrationFailure{CalibrationError::kInitialisationFailed,
                                "unknown camera model '" + cameras[c].model + "'"};
    for (std::size_t v = 0; v < cam.input->views.size(); ++v)
      if (static_cast<int>(cam.input->views[v].corner_ids.size()) >= options.min_corners_per_view)
        cam.usable.push_back(static_cast<int>(v));
    if (cam.usable.empty())
      return CalibrationFailure{CalibrationError::kTargetNeverSeen,
                                cam.input->label + ": the target was never seen with at least " +
                                    std::to_string(options.min_corners_per_view) + " corners in " +
                                    std::to_string(cam.input->views.size()) + " views"};
    if (static_cast<int>(cam.usable.size()) < options.min_views)
      return CalibrationFailure{CalibrationError::kTooFewViews,
                                cam.input->label + ": only " + std::to_string(cam.usable.size()) +
                                    " usable views, at least " + std::to_string(options.min_views) +
                                    " needed (show the target in more places of the image)"};
    Eigen::VectorXd init;
    if (cam.input->initial_params) {
      init = *cam.input->initial_params;
      std::string error;
      if (!GenericCamera::create(cam.input->model, init, &error))
        return CalibrationFailure{CalibrationError::kInitialisationFailed,
                                  cam.input->label + ": initial parameters: " + error};
    } else {
      report(options, cam.input->label + ": initialising " + cam.input->model + " intrinsics from " +
                          std::to_string(cam.usable.size()) + " views");
      init = initialIntrinsics(*cam.input, target, cam.usable);
    }
    // The double sphere's focal length and xi trade off near the image centre (the centre focal
    // length is fx/(1 + xi)), and the cost has separate minima along that valley: without a
    // user start, solve from three values of xi at the same centre focal length and keep the
    // lowest cost.
    std::vector<Eigen::VectorXd> starts = {init};
    if (!cam.input->initial_params && cam.input->model == "ds") {
      for (const double xi : {-0.3, 0.4}) {
        Eigen::VectorXd start = init;
        start[0] = init[0] * (1 + xi);
        start[1] = init[1] * (1 + xi);
        start[4] = xi;
        starts.push_back(start);
      }
    }
    const std::vector<int> usable = cam.usable;
    std::optional<CameraState> best;
    std::optional<CalibrationFailure> last_failure;
    for (std::size_t k = 0; k < starts.size(); ++k) {
      CameraState trial;
      trial.input = cam.input;
      trial.params.assign(starts[k].data(), starts[k].data() + starts[k].size());
      const auto camera = GenericCamera::create(cam.input->model, starts[k]);
      if (!camera) continue;
      for (int v : usable) {
        const auto pose = viewPose(*camera, target, cam.input->views[static_cast<std::size_t>(v)]);
        if (!pose) continue;
        trial.T_cam_board[v] = detail::PoseBlock::from(*pose);
        trial.usable.push_back(v);
      }
      if (static_cast<int>(trial.usable.size()) < options.min_views) {
        last_failure = CalibrationFailure{CalibrationError::kInitialisationFailed,
                                          cam.input->label + ": board poses could be initialised in only " +
                                              std::to_string(trial.usable.size()) + " views"};
        continue;
      }
      if (starts.size() > 1) {
        char line[160];
        std::snprintf(line, sizeof line, "%s: start %zu/%zu: fx %.1f, xi %.2f", cam.input->label.c_str(), k + 1,
                      starts.size(), starts[k][0], starts[k][4]);
        report(options, line);
      }
      ceres::Solver::Summary summary;
      if (auto failure = solveMono(target, trial, options, summary)) {
        last_failure = failure;
        continue;
      }
      if (!best || summary.final_cost < mono_summary.final_cost) {
        best = std::move(trial);
        mono_summary = summary;
      }
    }
    if (!best)
      return last_failure ? *last_failure
                          : CalibrationFailure{CalibrationError::kInitialisationFailed,
                                               cam.input->label + ": no valid initial parameters"};
    cam = std::move(*best);
  }

  IntrinsicResult result;
  std::map<int, detail::PoseBlock> T_l_b = state[0].T_cam_board;
  std::optional<detail::PoseBlock> T_r_l;
  ceres::Problem problem;
  int corners = 0;
  if (state.size() == 2) {
    std::vector<Eigen::Isometry3d> T_r_l_samples;
    for (const auto& [v, pose_r] : state[1].T_cam_board) {
      const auto it = state[0].T_cam_board.find(v);
      if (it != state[0].T_cam_board.end())
        T_r_l_samples.push_back(pose_r.toIsometry() * it->second.toIsometry().inverse());
    }
    if (T_r_l_samples.empty())
      return CalibrationFailure{CalibrationError::kNoCommonViews,
                                "no view shows the target to both cameras: T_cam_l_cam_r cannot be "
                                "estimated"};
    T_r_l = detail::PoseBlock::from(averagePose(T_r_l_samples));
    for (const auto& [v, pose_r] : state[1].T_cam_board)
      if (!T_l_b.count(v)) T_l_b[v] = detail::PoseBlock::from(T_r_l->toIsometry().inverse() * pose_r.toIsometry());
    T_r_l->addTo(problem);
  }
  for (auto& [v, pose] : T_l_b) pose.addTo(problem);
  for (std::size_t c = 0; c < state.size(); ++c) {
    addIntrinsicsBlock(problem, state[c]);
    for (int v : state[c].usable)
      corners += addCameraCorners(problem, target, state[c], cameras[c].views[static_cast<std::size_t>(v)],
                                  state[c].params.data(), T_l_b.at(v), c == 1 ? &*T_r_l : nullptr,
                                  options.huber_px);
  }
  if (state.size() == 2) {
    ceres::Solver::Options so = solverOptions(options);
    detail::ProgressCallback callback("stereo", options.progress, corners);
    so.callbacks.push_back(&callback);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
      return CalibrationFailure{CalibrationError::kDiverged,
                                "the stereo solve failed: " + failureSummary(summary)};
    result.initial_cost = summary.initial_cost;
    result.final_cost = summary.final_cost;
    result.iterations = static_cast<int>(summary.iterations.size());
  } else {
    result.initial_cost = mono_summary.initial_cost;
    result.final_cost = mono_summary.final_cost;
    result.iterations = static_cast<int>(mono_summary.iterations.size());
  }

  std::vector<std::vector<double>> stddevs(state.size());
  std::vector<Eigen::MatrixXd> covariances(state.size());  // unscaled; empty: rank deficient
  if (options.covariance) {
    report(options, "computing parameter covariance");
    ceres::Covariance::Options co;
    co.num_threads = options.num_threads;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> blocks;
    for (auto& cam : state) blocks.emplace_back(cam.params.data(), cam.params.data());
    if (T_r_l) {
      blocks.emplace_back(T_r_l->q.data(), T_r_l->q.data());
      blocks.emplace_back(T_r_l->t.data(), T_r_l->t.data());
      blocks.emplace_back(T_r_l->q.data(), T_r_l->t.data());
    }
    if (covariance.Compute(blocks, &problem)) {
      const double dof = std::max(1, 2 * corners - problem.NumParameters());
      const double sigma2 = 2.0 * result.final_cost / dof;
      if (T_r_l) result.T_cam_l_cam_r_stddev = inverseStddev(covariance, *T_r_l, sigma2);
      for (std::size_t c = 0; c < state.size(); ++c) {
        const int n = static_cast<int>(state[c].params.size());
        Eigen::MatrixXd cov(n, n);  // symmetric: row- or column-major read the same
        if (!covariance.GetCovarianceBlock(state[c].params.data(), state[c].params.data(), cov.data()))
          continue;
        covariances[c] = cov;  // correlations do not depend on the scale
        for (int i = 0; i < n; ++i) stddevs[c].push_back(std::sqrt(std::max(0.0, cov(i, i) * sigma2)));
      }
    }
  }
  if (T_r_l) result.T_cam_l_cam_r = T_r_l->toIsometry().inverse();
  for (std::size_t c = 0; c < state.size(); ++c) {
    const Eigen::VectorXd p = Eigen::Map<const Eigen::VectorXd>(
        state[c].params.data(), static_cast<Eigen::Index>(state[c].params.size()));
    std::string error;
    if (!GenericCamera::create(state[c].input->model, p, &error))
      return CalibrationFailure{CalibrationError::kDiverged,
                                state[c].input->label + ": the solve left the model's domain: " + error};
    result.cameras.push_back(evaluateCamera(target, state[c], T_l_b,
                                            c == 1 ? std::optional(T_r_l->toIsometry()) : std::nullopt));
    result.cameras[c].param_stddev = stddevs[c];
    if (options.covariance) {
      intrinsicSeparability(result.cameras[c], state[c].input->model, covariances[c], options);
      if (!result.cameras[c].degeneracy_warning.empty())
        report(options, "WARNING: " + result.cameras[c].degeneracy_warning);
    }
    if (!(result.cameras[c].rms_px <= options.max_rms_px))
      return CalibrationFailure{CalibrationError::kDiverged,
                                state[c].input->label + ": the solve diverged: final RMS " +
                                    std::to_string(result.cameras[c].rms_px) + " px exceeds " +
                                    std::to_string(options.max_rms_px) +
                                    " px (wrong target description, model or detections?)"};
  }
  const int num_views = static_cast<int>(cameras[0].views.size());
  result.T_cam_l_board.assign(static_cast<std::size_t>(num_views), std::nullopt);
  for (const auto& [v, pose] : T_l_b) result.T_cam_l_board[static_cast<std::size_t>(v)] = pose.toIsometry();
  result.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace telesphere::calib
