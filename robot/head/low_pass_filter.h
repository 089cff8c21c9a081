// SPDX-License-Identifier: MIT
/// @brief PoseLowPassFilter: the recursive first-order low-pass filter of the head target (paper
///        §III-C: cut-off 100 Hz), exact for variable time steps.
///
/// The continuous filter ẋ = ω_c·(u − x), ω_c = 2π·f_c, discretised exactly for an input held
/// over each step (zero-order hold): x ← x + α(dt)·(u − x) with α(dt) = 1 − exp(−ω_c·dt). So two
/// steps of dt/2 towards the same input give exactly one step of dt, whatever the sample times.
/// Position is filtered in R³; rotation along the geodesic: R ← slerp(R, R_u, α) (the same
/// exactness holds, slerp towards a fixed rotation composes like the scalar case).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>

#include "calib/debug_assert.h"

namespace telesphere::robot::head {

class PoseLowPassFilter {
 public:
  /// cutoff_hz > 0; +infinity turns the filter off (output = input).
  explicit PoseLowPassFilter(double cutoff_hz) : cutoff_hz_(cutoff_hz) {
    TS_ASSERT(cutoff_hz > 0, cutoff_hz);
  }

  /// α(dt) = 1 − exp(−2π·f_c·dt) for dt_ns ≥ 0: the fraction of the way to the input covered in
  /// dt. 0 for dt = 0, → 1 for dt ≫ 1/f_c, exactly 1 when the filter is off.
  static double alpha(double cutoff_hz, std::int64_t dt_ns) {
    TS_ASSERT(dt_ns >= 0, dt_ns);
    if (std::isinf(cutoff_hz)) return 1.0;
    return -std::expm1(-2.0 * M_PI * cutoff_hz * static_cast<double>(dt_ns) * 1e-9);
  }

  double cutoffHz() const { return cutoff_hz_; }
  /// Changes the cut-off (> 0, +inf: off) from the next update on, keeping the state.
  void setCutoffHz(double cutoff_hz) {
    TS_ASSERT(cutoff_hz > 0, cutoff_hz);
    cutoff_hz_ = cutoff_hz;
  }
  bool initialised() const { return initialised_; }

  /// Restarts the filter at T (robot frame) at time t_ns.
  void reset(const Eigen::Isometry3d& T, std::int64_t t_ns) {
    p_ = T.translation();
    q_ = Eigen::Quaterniond(T.linear()).normalized();
    t_ns_ = t_ns;
    initialised_ = true;
  }

  /// Feeds the input T observed at t_ns (≥ the previous time; an earlier one is treated as
  /// dt = 0) and returns the filtered pose. The first call after construction resets.
  Eigen::Isometry3d update(const Eigen::Isometry3d& T, std::int64_t t_ns) {
    if (!initialised_) {
      reset(T, t_ns);
      return output();
    }
    const double a = alpha(cutoff_hz_, std::max<std::int64_t>(0, t_ns - t_ns_));
    p_ += a * (T.translation() - p_);
    q_ = q_.slerp(a, Eigen::Quaterniond(T.linear()).normalized()).normalized();
    t_ns_ = std::max(t_ns_, t_ns);
    return output();
  }

  Eigen::Isometry3d output() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q_.toRotationMatrix();
    T.translation() = p_;
    return T;
  }

 private:
  double cutoff_hz_;
  bool initialised_ = false;
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  std::int64_t t_ns_ = 0;
};

}  // namespace telesphere::robot::head
