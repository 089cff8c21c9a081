// SPDX-License-Identifier: MIT
/// @brief A camera that replays pre-recorded (or pre-rendered) frames at a fixed rate, in real
///        time: frame k is due at start + k/fps and carries that instant as its capture time, as
///        a hardware-timestamped camera would. Used to measure the video path without the cost of
///        rendering (telesphere-bench pipeline) and by tests. Two replay cameras given the same
///        start instant behave like a hardware-triggered stereo pair.
///
/// A consumer that falls behind does not get old frames: like a camera whose buffers overrun,
/// the frames it missed are counted as lost and it gets the newest due frame.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robot/cameras/camera_source.h"
#include "robot/clock/clock.h"

namespace telesphere::robot::cameras {

struct ReplayCameraConfig {
  std::string name = "replay";
  double fps = 45.0;
  std::int64_t start_ns = 0;  ///< host clock instant of frame 0; 0: the moment start() is called
  std::uint32_t exposure_us = 5000;
};

class ReplayCamera final : public CameraSource {
 public:
  /// `frames` are cycled; their capture_ns/sequence are replaced, their pixels shared. `clock`
  /// must advance in real time (SteadyClock): nextFrame() sleeps until a frame is due.
  ReplayCamera(const clock::Clock& clock, std::vector<CameraFrame> frames, const ReplayCameraConfig& config);

  std::string name() const override { return config_.name; }
  bool start(std::string* error) override;
  void stop() override;
  std::optional<CameraFrame> nextFrame(std::chrono::milliseconds timeout) override;
  CameraStats stats() const override;

 private:
  const clock::Clock& clock_;
  std::vector<CameraFrame> frames_;
  ReplayCameraConfig config_;
  std::int64_t period_ns_ = 0;
  std::int64_t start_ns_ = 0;
  std::int64_t next_index_ = 0;  ///< the first frame not yet delivered
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> delivered_{0}, lost_{0};
};

}  // namespace telesphere::robot::cameras
