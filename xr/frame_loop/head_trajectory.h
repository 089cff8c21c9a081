// SPDX-License-Identifier: MIT
/// @brief A scripted head motion for runs without a headset (offscreen mode, tests, the demo):
///        T_vr_hmd over time, read from CSV and sampled at any time by linear interpolation of
///        the position and slerp of the orientation.
///
/// CSV: one pose per line, `t, px, py, pz, qx, qy, qz, qw` — t in seconds from the start
/// (strictly increasing), position in metres in the VR (stage) frame, unit quaternion (it is
/// normalised; a zero or non-finite one is an error). An optional header line starting with a
/// letter and `#` comment lines are skipped. Before the first sample the first pose holds, after
/// the last the last one (or the trajectory loops, see sample()).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::xr::frame_loop {

struct HeadPoseSample {
  double t_s = 0.0;
  Eigen::Vector3d p_vr_hmd = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_vr_hmd = Eigen::Quaterniond::Identity();
};

class HeadTrajectory {
 public:
  /// Parses CSV text; nothing, with "<name>:<line>: <what>" in *error, on any bad line.
  static std::optional<HeadTrajectory> parse(const std::string& text, const std::string& name,
                                             std::string* error);
  static std::optional<HeadTrajectory> load(const std::string& path, std::string* error);
  /// Built from samples (must be non-empty with increasing times; asserts otherwise).
  explicit HeadTrajectory(std::vector<HeadPoseSample> samples);

  /// T_vr_hmd at t_s; with `loop`, t_s wraps around the trajectory's duration.
  Eigen::Isometry3d sample(double t_s, bool loop = false) const;
  double durationS() const { return samples_.back().t_s - samples_.front().t_s; }
  const std::vector<HeadPoseSample>& samples() const { return samples_; }

  /// A gentle look-around for the demo: standing at (0, 1.6, 0) (y up), yaw ±30°, pitch ±10°,
  /// a 10 cm side step, over `duration_s`, sampled at 100 Hz.
  static HeadTrajectory demo(double duration_s = 8.0);

 private:
  std::vector<HeadPoseSample> samples_;
};

}  // namespace telesphere::xr::frame_loop
