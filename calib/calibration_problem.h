// SPDX-License-Identifier: MIT
/// @brief Internal to calib: pieces the Ceres problems of the intrinsic and hand-eye calibrations
///        share: camera models built once per parameter value (the double sphere scans for its
///        validity bound in its constructor), poses as Eigen quaternion + translation blocks,
///        parameter bounds per model.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace telesphere::calib::detail {

inline bool sameScalar(double a, double b) { return a == b; }
template <typename J>
bool sameScalar(const J& a, const J& b) {
  return a.a == b.a && a.v == b.v;
}

/// The camera of type Cam built from params[0..N): Ceres evaluates every residual of one camera
/// with the same parameter values (and, as Jets, the same derivative seeds), so a two-entry
/// cache per thread and type makes construction once per camera and evaluation.
template <typename Cam>
const Cam& cachedCamera(const typename Cam::Scalar* params) {
  using T = typename Cam::Scalar;
  constexpr int N = Cam::kNumParams;
  struct Entry {
    std::array<T, N> key;
    std::optional<Cam> camera;
  };
  thread_local std::array<Entry, 2> cache;
  thread_local int next = 0;
  for (Entry& e : cache) {
    if (!e.camera) continue;
    bool same = true;
    for (int i = 0; i < N && same; ++i) same = sameScalar(e.key[i], params[i]);
    if (same) return *e.camera;
  }
  Entry& e = cache[static_cast<std::size_t>(next)];
  next ^= 1;
  for (int i = 0; i < N; ++i) e.key[static_cast<std::size_t>(i)] = params[i];
  e.camera.emplace(Eigen::Map<const typename Cam::Params>(params));
  return *e.camera;
}

/// A pose block: Eigen quaternion (x, y, z, w) then translation, metres.
struct PoseBlock {
  std::array<double, 4> q{0, 0, 0, 1};
  std::array<double, 3> t{0, 0, 0};

  static PoseBlock from(const Eigen::Isometry3d& T) {
    PoseBlock b;
    const Eigen::Quaterniond q(T.linear());
    b.q = {q.x(), q.y(), q.z(), q.w()};
    b.t = {T.translation().x(), T.translation().y(), T.translation().z()};
    return b;
  }
  Eigen::Isometry3d toIsometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
    return T;
  }
  void addTo(ceres::Problem& problem) {
    problem.AddParameterBlock(q.data(), 4, new ceres::EigenQuaternionManifold);
    problem.AddParameterBlock(t.data(), 3);
  }
};

/// T·p for a pose given as quaternion (x, y, z, w) and translation arrays.
template <typename T, typename P>
Eigen::Matrix<T, 3, 1> transformPoint(const T* q, const T* t, const P& p) {
  const Eigen::Map<const Eigen::Quaternion<T>> rotation(q);
  return rotation * p + Eigen::Map<const Eigen::Matrix<T, 3, 1>>(t);
}

/// Lower and upper bound of each parameter of `model` (kalibr order); ±∞ where unbounded.
inline std::vector<std::pair<double, double>> paramBounds(const std::string& model, int width,
                                                          int height) {
  const double inf = INFINITY;
  std::vector<std::pair<double, double>> b = {
      {1.0, inf}, {1.0, inf}, {0.0, double(width)}, {0.0, double(height)}};
  if (model == "ds") {
    b.push_back({-0.99, 1e3});  // xi ∈ (−1, 1e3]
    b.push_back({0.0, 1.0});    // alpha
  } else if (model == "eucm") {
    b.push_back({0.0, 1.0});    // alpha
    b.push_back({1e-6, 1e3});   // beta ∈ (0, 1e3]
  } else if (model == "kb4") {
    for (int i = 0; i < 4; ++i) b.push_back({-10.0, 10.0});
  } else {  // pinhole-radtan
    b.push_back({-10.0, 10.0});
    b.push_back({-10.0, 10.0});
    b.push_back({-1.0, 1.0});
    b.push_back({-1.0, 1.0});
  }
  return b;
}

inline void setBounds(ceres::Problem& problem, double* params,
                      const std::vector<std::pair<double, double>>& bounds) {
  for (std::size_t i = 0; i < bounds.size(); ++i) {
    if (std::isfinite(bounds[i].first))
      problem.SetParameterLowerBound(params, static_cast<int>(i), bounds[i].first);
    if (std::isfinite(bounds[i].second))
      problem.SetParameterUpperBound(params, static_cast<int>(i), bounds[i].second);
  }
}

/// Forwards Ceres's iterations to a progress callback.
class ProgressCallback : public ceres::IterationCallback {
 public:
  ProgressCallback(std::string stage, std::function<void(const std::string&)> out, int residuals)
      : stage_(std::move(stage)), out_(std::move(out)), residuals_(residuals) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (out_) {
      char line[160];
      std::snprintf(line, sizeof line, "%s: iteration %d, cost %.6g, ~RMS %.4f px", stage_.c_str(),
                    s.iteration, s.cost, std::sqrt(2.0 * s.cost / std::max(1, residuals_)));
      out_(line);
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  std::string stage_;
  std::function<void(const std::string&)> out_;
  int residuals_;
};

/// The reprojection residual r = project(p_cam) − observed (px). A point the model cannot project
/// contributes nothing this step (r = 0) instead of failing the solver's step.
template <typename Cam, typename T>
bool reprojectionResidual(const Cam& cam, const Eigen::Matrix<T, 3, 1>& p_cam,
                          const Eigen::Vector2d& observed_px, T* r) {
  typename Cam::Vec2 px;
  if (!cam.project(p_cam, px)) {
    r[0] = T(0);
    r[1] = T(0);
    return true;
  }
  r[0] = px[0] - T(observed_px.x());
  r[1] = px[1] - T(observed_px.y());
  return true;
}

}  // namespace telesphere::calib::detail
