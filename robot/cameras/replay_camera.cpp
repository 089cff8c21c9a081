// SPDX-License-Identifier: MIT
/// @brief ReplayCamera: due times on a fixed grid, sleeping in short slices so stop() is prompt.
#include "robot/cameras/replay_camera.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

namespace telesphere::robot::cameras {

ReplayCamera::ReplayCamera(const clock::Clock& clock, std::vector<CameraFrame> frames,
                           const ReplayCameraConfig& config)
    : clock_(clock), frames_(std::move(frames)), config_(config) {}

bool ReplayCamera::start(std::string* error) {
  if (frames_.empty()) {
    *error = config_.name + ": no frames to replay";
    return false;
  }
  if (!(config_.fps > 0.0 && config_.fps <= 10000.0)) {
    *error = config_.name + ": frame rate " + std::to_string(config_.fps) + " Hz is outside (0, 10000]";
    return false;
  }
  for (const CameraFrame& f : frames_) {
    if (!f.pixels || f.width <= 0 || f.height <= 0 ||
        f.pixels->size() < static_cast<std::size_t>(f.stride_bytes) * f.height) {
      *error = config_.name + ": a replay frame has no or too few pixel bytes";
      return false;
    }
  }
  period_ns_ = std::llround(1e9 / config_.fps);
  start_ns_ = config_.start_ns != 0 ? config_.start_ns : clock_.nowNs();
  next_index_ = 0;
  running_ = true;
  return true;
}

void ReplayCamera::stop() { running_ = false; }

std::optional<CameraFrame> ReplayCamera::nextFrame(std::chrono::milliseconds timeout) {
  if (!running_) return std::nullopt;
  const std::int64_t deadline_ns = clock_.nowNs() + timeout.count() * 1'000'000;
  std::int64_t due_ns = start_ns_ + next_index_ * period_ns_;
  for (;;) {
    if (!running_) return std::nullopt;
    const std::int64_t now_ns = clock_.nowNs();
    if (now_ns >= due_ns) break;
    if (now_ns >= deadline_ns) return std::nullopt;
    const std::int64_t slice_ns = std::min({due_ns - now_ns, deadline_ns - now_ns, std::int64_t{5'000'000}});
    std::this_thread::sleep_for(std::chrono::nanoseconds(slice_ns));
  }
  // Late: skip to the newest due frame, counting the skipped ones as lost (buffer overrun).
  const std::int64_t newest = (clock_.nowNs() - start_ns_) / period_ns_;
  if (newest > next_index_) {
    lost_ += static_cast<std::uint64_t>(newest - next_index_);
    next_index_ = newest;
    due_ns = start_ns_ + next_index_ * period_ns_;
  }
  CameraFrame frame = frames_[static_cast<std::size_t>(next_index_) % frames_.size()];
  frame.capture_ns = due_ns;
  frame.sequence = static_cast<std::uint64_t>(next_index_);
  frame.exposure_us = config_.exposure_us;
  frame.timestamp_from_hardware = true;  // an exact grid, like a camera's own clock
  ++next_index_;
  ++delivered_;
  return frame;
}

CameraStats ReplayCamera::stats() const {
  CameraStats s;
  s.frames = delivered_;
  s.lost = lost_;
  return s;
}

}  // namespace telesphere::robot::cameras
