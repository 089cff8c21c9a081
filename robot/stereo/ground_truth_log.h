// SPDX-License-Identifier: MIT
/// @brief The simulation's ground truth for each stereo frame sent (the end-to-end truth the
///        experiments and the loop test compare with, app/bench/truth): where each camera really was
///        at its capture time — the simulated arm's noise-free joints through the true
///        calibration, whatever the joint-state buffer stamped into the frame — and the nominal
///        mapping T_robot_vr in force when the frame went out. CSV, one row per frame, written
///        from the video thread; a real robot has no such file.
///
/// Columns: sequence, capture_ns_left, capture_ns_right (robot clock), then for the left and
/// the right camera its true T_robot_cam as tx ty tz qx qy qz qw (m; empty when the truth did
/// not cover the capture time), mapping_set (0/1), T_robot_vr as tx … qw.
#pragma once

#include <cstdint>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>

#include "robot/head/joint_state_buffer.h"
#include "robot/link/telesphere_link.pb.h"
#include "robot/stereo/stereo_pairer.h"

namespace telesphere::robot::stereo {

class GroundTruthLog {
 public:
  /// Creates `path` with its header; nothing, with the reason in *error, when it cannot.
  /// `truth` (the arm's true joints through the true calibration) must outlive the log.
  static std::unique_ptr<GroundTruthLog> open(const std::string& path, const head::JointStateBuffer& truth,
                                              std::string* error);

  /// One row for the frame sent as `sequence`.
  void frameSent(const StereoFrame& pair, std::uint64_t sequence, const link::proto::NominalMapping& mapping);
  /// Rows written so far.
  std::uint64_t rows() const;

 private:
  GroundTruthLog(std::ofstream out, const head::JointStateBuffer& truth);

  mutable std::mutex mutex_;
  std::ofstream out_;
  const head::JointStateBuffer& truth_;
  std::uint64_t rows_ = 0;
};

}  // namespace telesphere::robot::stereo
