// SPDX-License-Identifier: MIT
/// @brief Collects the robot's telemetry samples (one HeadTick per 100 Hz head-loop tick, one
///        SentFrame per stereo frame sent) from the threads that make them and hands them out in
///        numbered batches (DESIGN.md §7: every sample, stamped at its source; numbered so the
///        console counts what it lost). The head loop publishes a batch every few ticks.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::robot::telemetry {

class TelemetryBatcher {
 public:
  /// Samples waiting beyond this are dropped (nobody takes batches): counted, never unbounded.
  static constexpr int kMaxPendingSamples = 10000;

  void addTick(const link::proto::HeadTick& tick);
  void addFrame(const link::proto::SentFrame& frame);

  /// The samples collected since the last call as the next batch (numbered from 1); nothing when
  /// there are none.
  std::optional<link::proto::RobotTelemetry> takeBatch();

  std::uint64_t batches() const;
  std::uint64_t droppedSamples() const;

 private:
  mutable std::mutex mutex_;
  link::proto::RobotTelemetry pending_;
  std::uint64_t batches_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace telesphere::robot::telemetry
