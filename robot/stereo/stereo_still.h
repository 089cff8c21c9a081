// SPDX-License-Identifier: MIT
/// @brief Full-resolution stereo stills for calibration (paper §III-B, DESIGN.md §6; the link's
///        calibration_capture request): the first pair the video path sends after the request,
///        both images as 8-bit grey at the cameras' own resolution (Bayer demosaiced, RGB to
///        Rec. 601 luma), with the head joints interpolated at the pair's capture time — only once
///        joint states on both sides of that time are there (waiting for the one after up to the
///        timeout), so a sample's joints are never extrapolated.
///
/// Where a manipulator carries the wrist marker (hand-eye calibration), its reported joints are
/// interpolated at the capture time too, under the same rule (reports on both sides of it).
///
///   video path ──offer(pair)──▶ StereoStillTaker ◀──take()── control thread (blocks ≤ timeout)
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "robot/clock/clock.h"
#include "robot/head/joint_state_buffer.h"
#include "robot/link/telesphere_link.pb.h"
#include "robot/stereo/stereo_pairer.h"

namespace telesphere::robot::stereo {

class StereoStillTaker {
 public:
  /// `manipulator`: the manipulator's reported joints (its buffer's flange pose is T_mount_wrist),
  /// or null when the robot has none.
  StereoStillTaker(const head::JointStateBuffer& joints, const clock::Clock& clock, const head::JointStateBuffer* manipulator = nullptr)
      : joints_(joints), clock_(clock), manipulator_(manipulator) {}

  /// Every pair the video path sends (cheap: the pixels are shared, nothing is converted here).
  void offer(const StereoFrame& pair, std::uint64_t sequence);

  /// Waits for the first pair captured after now and for joint states bracketing its capture
  /// time; false with the reason (no pair within `timeout`, joints missing) otherwise.
  bool take(link::proto::CalibrationStill* still, std::chrono::milliseconds timeout, std::string* error);

  /// Stills taken so far.
  std::uint64_t taken() const;
  /// take() calls waiting for a pair now: a test offers once one waits, without sleeping.
  int takersWaiting() const { return takers_waiting_.load(); }

 private:
  const head::JointStateBuffer& joints_;
  const clock::Clock& clock_;
  const head::JointStateBuffer* manipulator_;
  mutable std::mutex mutex_;
  std::condition_variable offered_;
  std::optional<std::pair<StereoFrame, std::uint64_t>> newest_;
  std::uint64_t taken_ = 0;
  std::atomic<int> takers_waiting_{0};
};

/// One camera frame as 8-bit grey rows without padding; false with the reason.
bool toGray8(const cameras::CameraFrame& frame, std::string* gray, std::string* error);

}  // namespace telesphere::robot::stereo
