// SPDX-License-Identifier: MIT
/// @brief Where a simulated camera really is at a capture time: T_robot_cam(t) from the arm's
///        noise-free joint states (the truth buffer, fed at every physics step) through the true
///        calibration. The synthetic cameras render each frame after its readout, by when the
///        head loop has normally simulated past the capture time; when it lags (a loaded
///        machine), at(t) waits for it up to a bound: a frame drawn at a made-up pose would put a
///        silent error into everything downstream (calibration stills above all). Only before the
///        arm's first state is the initial configuration's pose the truth; any other fallback is
///        counted and said on stderr (every 100th).
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>

#include <Eigen/Geometry>

#include "robot/clock/clock.h"
#include "robot/head/joint_state_buffer.h"

namespace telesphere::robot::stereo {

class TrueCameraPoses {
 public:
  /// `truth`: the arm's true joint states with the true camera mount; `T_robot_cam0`: the left
  /// and right cameras at the arm's initial configuration. Both must outlive this object.
  TrueCameraPoses(const head::JointStateBuffer& truth, const clock::Clock& clock,
                  const std::array<Eigen::Isometry3d, 2>& T_robot_cam0,
                  std::chrono::milliseconds max_wait = std::chrono::milliseconds(2000))
      : truth_(truth), clock_(clock), T_robot_cam0_(T_robot_cam0), max_wait_(max_wait) {}

  /// T_robot_cam of camera `side` at t_ns (steady ns); thread-safe.
  Eigen::Isometry3d at(cameras::CameraSide side, std::int64_t t_ns) const;

  /// Poses that fell back to the initial one although the arm had reported states.
  std::uint64_t fallbacks() const { return fallbacks_; }

 private:
  const head::JointStateBuffer& truth_;
  const clock::Clock& clock_;
  std::array<Eigen::Isometry3d, 2> T_robot_cam0_;
  std::chrono::milliseconds max_wait_;
  mutable std::atomic<std::uint64_t> fallbacks_{0};
};

}  // namespace telesphere::robot::stereo
