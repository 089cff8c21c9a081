// SPDX-License-Identifier: MIT
/// @brief HandEyeCollector (see hand_eye_collector.h).
#include "console/calibration/hand_eye_collector.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace telesphere::console::calibration {
namespace {

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

}  // namespace

std::string HandEyeDoneRule::describe() const {
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "%d samples · head and wrist rotation axes spread ≥ %.0f° · |σ_t| ≤ %.1f mm and |σ_r| ≤ %.2f° for "
                "T_flange_cam_l and T_robot_mount · RMS ≤ %.1f px",
                min_samples, min_axis_spread_deg, max_translation_std_mm, max_rotation_std_deg, max_rms_px);
  return buf;
}

HandEyeCollector::HandEyeCollector(calib::SystemCalibration cameras, WristMarker marker, HandEyeCollectorOptions options)
    : cameras_(std::move(cameras)), marker_(std::move(marker)), options_(options) {}

bool HandEyeCollector::offer(const HandEyeStillSample& sample, std::string* reason) {
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const calib::HandEyeSample& kept = samples_[i].sample;
    const double head = angleDeg(kept.T_robot_flange.linear(), sample.sample.T_robot_flange.linear());
    const double wrist = angleDeg(kept.T_mount_wrist.linear(), sample.sample.T_mount_wrist.linear());
    if (head < options_.min_rotation_deg && wrist < options_.min_rotation_deg) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "too close to sample %zu (head %.1f°, wrist %.1f°; needs %.1f° in either)", i + 1,
                    head, wrist, options_.min_rotation_deg);
      *reason = buf;
      return false;
    }
  }
  samples_.push_back(sample);
  rms_px_.push_back(NAN);
  return true;
}

void HandEyeCollector::remove(std::size_t index) {
  if (index >= samples_.size()) return;
  samples_.erase(samples_.begin() + std::ptrdiff_t(index));
  rms_px_.erase(rms_px_.begin() + std::ptrdiff_t(index));
}

int HandEyeCollector::removeOutliers() {
  const std::vector<bool> out = outliers();
  int removed = 0;
  for (std::size_t i = out.size(); i-- > 0;) {
    if (!out[i]) continue;
    remove(i);
    ++removed;
  }
  return removed;
}

calib::HandEyeOptions HandEyeCollector::solverOptions() const {
  calib::HandEyeOptions o;
  o.min_samples = options_.auto_solve_from;
  o.min_axis_spread_deg = options_.rule.min_axis_spread_deg;
  o.T_flange_cam_l_guess = cameras_.T_flange_cam_l;  // below 10 samples the closed form needs it
  return o;
}

calib::HandEyeIdentifiability HandEyeCollector::diversity() const {
  std::vector<calib::HandEyeSample> s;
  for (const auto& k : samples_) s.push_back(k.sample);
  return calib::checkHandEyeIdentifiability(s, solverOptions());
}

bool HandEyeCollector::solve(std::string* error, const std::function<void(const std::string&)>& progress) {
  result_.reset();
  std::fill(rms_px_.begin(), rms_px_.end(), NAN);
  std::vector<calib::HandEyeSample> s;
  for (const auto& k : samples_) s.push_back(k.sample);
  calib::HandEyeOptions o = solverOptions();
  o.progress = progress;
  auto solved = calib::calibrateHandEye(cameras_, marker_.size_m, s, o);
  if (!solved) {
    *error = solved.failure().message;
    return false;
  }
  result_ = *solved;
  for (const calib::HandEyeSampleFit& fit : result_->sample_fits)
    if (fit.index < rms_px_.size()) rms_px_[fit.index] = fit.rms_px;
  return true;
}

std::vector<double> HandEyeCollector::sampleRmsPx() const { return rms_px_; }

double HandEyeCollector::outlierBoundPx() const {
  std::vector<double> used;
  for (double r : rms_px_)
    if (std::isfinite(r)) used.push_back(r);
  if (used.size() < 3) return NAN;
  std::nth_element(used.begin(), used.begin() + std::ptrdiff_t(used.size() / 2), used.end());
  return std::max(options_.outlier_floor_px, options_.outlier_factor * used[used.size() / 2]);
}

std::vector<bool> HandEyeCollector::outliers() const {
  const double bound = outlierBoundPx();
  std::vector<bool> out(rms_px_.size(), false);
  for (std::size_t i = 0; i < rms_px_.size(); ++i) out[i] = std::isfinite(rms_px_[i]) && rms_px_[i] > bound;
  return out;
}

DoneCheck HandEyeCollector::check() const {
  const HandEyeDoneRule& rule = options_.rule;
  DoneCheck c;
  char buf[240];
  if (int(samples_.size()) < rule.min_samples) {
    std::snprintf(buf, sizeof buf, "%zu of %d samples", samples_.size(), rule.min_samples);
    c.unmet.push_back(buf);
  }
  const calib::HandEyeIdentifiability d = diversity();
  if (d.head_axis_spread_deg < rule.min_axis_spread_deg || d.wrist_axis_spread_deg < rule.min_axis_spread_deg) {
    std::snprintf(buf, sizeof buf, "rotation axes spread: head %.1f°, wrist %.1f° (need %.0f° each)",
                  d.head_axis_spread_deg, d.wrist_axis_spread_deg, rule.min_axis_spread_deg);
    c.unmet.push_back(buf);
  }
  if (!result_) {
    c.unmet.push_back("no solution yet");
    return c;
  }
  static constexpr const char* kNames[2] = {"T_flange_cam_l", "T_robot_mount"};
  for (std::size_t k = 0; k < 2; ++k) {
    const calib::PoseStddev& sd = result_->stddev[k];
    if (!sd.valid) {
      std::snprintf(buf, sizeof buf, "%s: no standard deviation (the problem is rank deficient)", kNames[k]);
      c.unmet.push_back(buf);
      continue;
    }
    const double t_mm = sd.translation_m.norm() * 1e3, r_deg = sd.rotation_deg.norm();
    if (t_mm > rule.max_translation_std_mm || r_deg > rule.max_rotation_std_deg) {
      std::snprintf(buf, sizeof buf, "%s: |σ_t| %.2f mm, |σ_r| %.3f° (need ≤ %.1f mm, ≤ %.2f°)", kNames[k], t_mm, r_deg,
                    rule.max_translation_std_mm, rule.max_rotation_std_deg);
      c.unmet.push_back(buf);
    }
  }
  const double rms = std::max(result_->rms_px_l, result_->rms_px_r);
  if (rms > rule.max_rms_px) {
    std::snprintf(buf, sizeof buf, "RMS %.2f px (need ≤ %.1f px)", rms, rule.max_rms_px);
    c.unmet.push_back(buf);
  }
  return c;
}

calib::SystemCalibration withHandEye(calib::SystemCalibration cameras, const calib::HandEyeResult& result) {
  cameras.T_flange_cam_l = result.T_flange_cam_l;
  cameras.T_robot_mount = result.T_robot_mount;
  cameras.T_wrist_marker = result.T_wrist_marker;
  return cameras;
}

std::optional<calib::SystemCalibration> HandEyeCollector::calibration() const {
  if (!result_) return std::nullopt;
  return withHandEye(cameras_, *result_);
}

}  // namespace telesphere::console::calibration
