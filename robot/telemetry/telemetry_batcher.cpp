// SPDX-License-Identifier: MIT
/// @brief TelemetryBatcher: a mutex-guarded batch under construction.
#include "robot/telemetry/telemetry_batcher.h"

namespace telesphere::robot::telemetry {

void TelemetryBatcher::addTick(const link::proto::HeadTick& tick) {
  std::lock_guard lock(mutex_);
  if (pending_.ticks_size() + pending_.frames_size() >= kMaxPendingSamples) {
    ++dropped_;
    return;
  }
  *pending_.add_ticks() = tick;
}

void TelemetryBatcher::addFrame(const link::proto::SentFrame& frame) {
  std::lock_guard lock(mutex_);
  if (pending_.ticks_size() + pending_.frames_size() >= kMaxPendingSamples) {
    ++dropped_;
    return;
  }
  *pending_.add_frames() = frame;
}

std::optional<link::proto::RobotTelemetry> TelemetryBatcher::takeBatch() {
  std::lock_guard lock(mutex_);
  if (pending_.ticks_size() == 0 && pending_.frames_size() == 0) return std::nullopt;
  link::proto::RobotTelemetry batch;
  batch.Swap(&pending_);
  batch.set_batch(++batches_);
  return batch;
}

std::uint64_t TelemetryBatcher::batches() const {
  std::lock_guard lock(mutex_);
  return batches_;
}

std::uint64_t TelemetryBatcher::droppedSamples() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace telesphere::robot::telemetry
