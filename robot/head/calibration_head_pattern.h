// SPDX-License-Identifier: MIT
/// @brief The paper's predefined sinusoidal head pattern for hand-eye sample collection (§III-B;
///        link CalibrationHeadPose.pattern_amplitude_deg): about a centre pose, yaw ±A, pitch
///        ±0.6·A and roll ±0.4·A (head axes: x forward, y left, z up) with periods 7 s, 5 s and
///        11 s, so the head turns about three axes and the pattern repeats only after 385 s.
///        The amplitude ramps up over the first 2 s so that the head starts from rest at the
///        centre; the position stays at the centre's.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace telesphere::robot::head {

inline constexpr double kMaxCalibrationPatternDeg = 30.0;

/// The pattern's head pose about T_robot_centre for the yaw, pitch and roll swings (each in
/// [−1, 1]) at amplitude `amplitude_rad`.
inline Eigen::Isometry3d calibrationPatternSwing(const Eigen::Isometry3d& T_robot_centre, double amplitude_rad,
                                                 double yaw, double pitch, double roll) {
  const Eigen::Matrix3d R_centre_head = (Eigen::AngleAxisd(amplitude_rad * yaw, Eigen::Vector3d::UnitZ()) *
                                         Eigen::AngleAxisd(0.6 * amplitude_rad * pitch, Eigen::Vector3d::UnitY()) *
                                         Eigen::AngleAxisd(0.4 * amplitude_rad * roll, Eigen::Vector3d::UnitX()))
                                            .toRotationMatrix();
  Eigen::Isometry3d T = T_robot_centre;
  T.linear() = T_robot_centre.linear() * R_centre_head;
  return T;
}

/// T_robot_head at `elapsed_ns` after the pattern started about T_robot_centre.
inline Eigen::Isometry3d calibrationPatternPose(const Eigen::Isometry3d& T_robot_centre, double amplitude_deg,
                                                std::int64_t elapsed_ns) {
  const double t = static_cast<double>(elapsed_ns) * 1e-9;
  const double a = amplitude_deg * M_PI / 180.0 * std::clamp(t / 2.0, 0.0, 1.0);
  const auto swing = [t](double period_s) { return std::sin(2.0 * M_PI * t / period_s); };
  return calibrationPatternSwing(T_robot_centre, a, swing(7.0), swing(5.0), swing(11.0));
}

}  // namespace telesphere::robot::head
