// SPDX-License-Identifier: MIT
/// @brief JointStateBuffer: the recent joint states of the head arm in time order, queried at any
///        timestamp, e.g. a camera image's capture time (DESIGN.md §2, §5).
///
/// Joints are interpolated linearly between the two samples around t, so the poses follow
/// forward kinematics exactly: T_robot_cam(t) = FK(q(t)) · T_flange_cam. (DESIGN.md §5 mentions
/// slerping poses; interpolating the joints is what the arm actually does between its 100 Hz
/// samples and keeps camera poses on the arm's real path.) Queries before the oldest sample, more
/// than max_extrapolation_ns after the newest, or across a gap wider than max_gap_ns (a dropped
/// connection) return nothing. Within the bound after the newest sample the last two samples are
/// extrapolated linearly (one sample: held).
///
/// Thread safety: one writer (push) and any number of concurrent readers, which may wait for a sample.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <shared_mutex>
#include <utility>
#include <vector>

#include "robot/cameras/camera_side.h"
#include "robot/head/head_geometry.h"
#include "robot/arm/joint_state.h"
#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot::head {

struct JointStateBufferConfig {
  std::size_t capacity = 512;                    ///< samples kept (5.12 s at 100 Hz)
  std::int64_t max_extrapolation_ns = 20'000'000;  ///< beyond the newest sample
  std::int64_t max_gap_ns = 100'000'000;         ///< widest gap interpolated across
};


class JointStateBuffer {
 public:
  explicit JointStateBuffer(const HeadGeometry& geometry, const JointStateBufferConfig& config = {});

  /// Appends a state. False (ignored) unless t_ns is newer than the newest sample and q finite.
  /// When full, the oldest sample is dropped.
  bool push(const arm::JointState& state);

  /// The camera mount T_robot_cam uses from now on (a calibration applied live).
  void setGeometry(const HeadGeometry& geometry);

  /// q(t_ns) in rad, or nothing outside the window (see the file comment).
  std::optional<arm::JointVector> jointsAt(std::int64_t t_ns) const;
  /// T_robot_flange(t_ns) = FK(q(t_ns)).
  std::optional<Eigen::Isometry3d> T_robot_flange(std::int64_t t_ns) const;
  /// T_robot_cam(t_ns) = FK(q(t_ns)) · T_flange_cam for the left or right camera.
  std::optional<Eigen::Isometry3d> T_robot_cam(cameras::CameraSide side, std::int64_t t_ns) const;

  std::size_t size() const;
  /// [oldest, newest] sample times, or nothing when empty.
  std::optional<std::pair<std::int64_t, std::int64_t>> window() const;
  /// The times of the samples on both sides of t_ns (newest ≤ t_ns, oldest ≥ t_ns), or nothing
  /// when t_ns is outside the window.
  std::optional<std::pair<std::int64_t, std::int64_t>> bracket(std::int64_t t_ns) const;

  /// Waits until the newest sample is at or after t_ns (woken by every push) or until `deadline`;
  /// true when it is. For readers that must not extrapolate (calibration stills) or that wait for
  /// a simulation to reach a time.
  bool waitForSampleAtOrAfter(std::int64_t t_ns, std::chrono::steady_clock::time_point deadline) const;
  /// Readers inside waitForSampleAtOrAfter now: a test pushes once a reader waits, without sleeping.
  int waitingReaders() const { return waiting_readers_.load(); }

 private:
  const arm::JointState& at(std::size_t i) const;  ///< i-th oldest; caller holds the lock

  arm::Xarm6Kinematics kinematics_;
  Eigen::Isometry3d T_flange_cam_l_, T_flange_cam_r_;
  JointStateBufferConfig config_;
  mutable std::shared_mutex mutex_;
  mutable std::condition_variable_any pushed_;
  mutable std::atomic<int> waiting_readers_{0};
  std::vector<arm::JointState> ring_;
  std::size_t begin_ = 0, size_ = 0;
};

}  // namespace telesphere::robot::head
