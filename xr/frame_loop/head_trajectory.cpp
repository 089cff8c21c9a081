// SPDX-License-Identifier: MIT
/// @brief HeadTrajectory: CSV parsing with line-numbered errors; lerp + slerp sampling.
#include "xr/frame_loop/head_trajectory.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "calib/debug_assert.h"

namespace telesphere::xr::frame_loop {

HeadTrajectory::HeadTrajectory(std::vector<HeadPoseSample> samples) : samples_(std::move(samples)) {
  TS_ASSERT(!samples_.empty());
  for (std::size_t i = 1; i < samples_.size(); ++i) TS_ASSERT(samples_[i].t_s > samples_[i - 1].t_s, i);
}

std::optional<HeadTrajectory> HeadTrajectory::parse(const std::string& text, const std::string& name,
                                                    std::string* error) {
  std::vector<HeadPoseSample> samples;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  const auto fail = [&](const std::string& what) {
    *error = name + ":" + std::to_string(line_number) + ": " + what;
    return std::nullopt;
  };
  while (std::getline(lines, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    if (std::isalpha(static_cast<unsigned char>(line[first])) && samples.empty() && line_number == 1)
      continue;  // header
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream in(line);
    double v[8];
    std::string token;
    int n = 0;
    while (in >> token) {
      if (n == 8) return fail("more than 8 values (expected t, px, py, pz, qx, qy, qz, qw)");
      char* end = nullptr;
      v[n] = std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size() || !std::isfinite(v[n]))
        return fail("'" + token + "' is not a finite number");
      ++n;
    }
    if (n != 8) return fail(std::to_string(n) + " values, expected 8 (t, px, py, pz, qx, qy, qz, qw)");
    HeadPoseSample s;
    s.t_s = v[0];
    s.p_vr_hmd = Eigen::Vector3d(v[1], v[2], v[3]);
    s.q_vr_hmd = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    const double norm = s.q_vr_hmd.norm();
    if (!(norm > 1e-6)) return fail("quaternion has zero length");
    s.q_vr_hmd.coeffs() /= norm;
    if (!samples.empty() && !(s.t_s > samples.back().t_s))
      return fail("time " + std::to_string(s.t_s) + " s does not increase");
    samples.push_back(s);
  }
  if (samples.empty()) {
    *error = name + ": no poses";
    return std::nullopt;
  }
  return HeadTrajectory(std::move(samples));
}

std::optional<HeadTrajectory> HeadTrajectory::load(const std::string& path, std::string* error) {
  std::ifstream file(path);
  if (!file) {
    *error = path + ": cannot open";
    return std::nullopt;
  }
  std::stringstream text;
  text << file.rdbuf();
  return parse(text.str(), path, error);
}

Eigen::Isometry3d HeadTrajectory::sample(double t_s, bool loop) const {
  const double t0 = samples_.front().t_s;
  if (loop && durationS() > 0.0) t_s = t0 + std::fmod(std::fmod(t_s - t0, durationS()) + durationS(), durationS());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t_s,
                                      [](double t, const HeadPoseSample& s) { return t < s.t_s; });
  if (after == samples_.begin() || after == samples_.end()) {
    const HeadPoseSample& s = after == samples_.begin() ? samples_.front() : samples_.back();
    T.linear() = s.q_vr_hmd.toRotationMatrix();
    T.translation() = s.p_vr_hmd;
    return T;
  }
  const HeadPoseSample& b = *after;
  const HeadPoseSample& a = *(after - 1);
  const double w = (t_s - a.t_s) / (b.t_s - a.t_s);
  T.linear() = a.q_vr_hmd.slerp(w, b.q_vr_hmd).toRotationMatrix();
  T.translation() = (1.0 - w) * a.p_vr_hmd + w * b.p_vr_hmd;
  return T;
}

HeadTrajectory HeadTrajectory::demo(double duration_s) {
  std::vector<HeadPoseSample> samples;
  const int n = std::max(2, static_cast<int>(duration_s * 100.0) + 1);
  for (int i = 0; i < n; ++i) {
    const double t = duration_s * i / (n - 1);
    const double phase = 2.0 * M_PI * t / duration_s;
    HeadPoseSample s;
    s.t_s = t;
    s.p_vr_hmd = Eigen::Vector3d(0.05 * std::sin(phase), 1.6, 0.0);
    const double yaw = (30.0 * M_PI / 180.0) * std::sin(phase);
    const double pitch = (10.0 * M_PI / 180.0) * std::sin(2.0 * phase);
    s.q_vr_hmd = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                 Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX());
    samples.push_back(s);
  }
  return HeadTrajectory(std::move(samples));
}

}  // namespace telesphere::xr::frame_loop
