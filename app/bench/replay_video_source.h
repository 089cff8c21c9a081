// SPDX-License-Identifier: MIT
/// @brief The robot side of the video path for benchmarks, in-process: two replay cameras
///        sharing a start instant (a triggered pair) → stereo pairing → parallel encode (MJPEG, or
///        the codec `config` names) → a link server on `endpoints`. Frames start flowing `delay` after construction (so a client
///        can subscribe first) and stop when it is destroyed.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "robot/cameras/replay_camera.h"
#include "robot/video/video_streamer.h"

namespace telesphere::bench {

struct ReplayVideoSource {
  robot::clock::SteadyClock clock;
  std::int64_t start_ns;  ///< frame 0 of both cameras
  link::LinkServer server;
  robot::cameras::ReplayCamera left, right;
  robot::stereo::StereoPairSource pairs;
  robot::video::VideoStreamer streamer;

  ReplayVideoSource(const link::LinkEndpoints& endpoints, const std::vector<robot::cameras::CameraFrame>& left_frames,
                    const std::vector<robot::cameras::CameraFrame>& right_frames, double rate_hz,
                    robot::video::StereoPosesAt poses, std::chrono::milliseconds delay,
                    const robot::video::VideoStreamerConfig& config = {})
      : start_ns(clock.nowNs() + delay.count() * 1'000'000),
        server(endpoints),
        left(clock, left_frames, cameraConfig("left", rate_hz)),
        right(clock, right_frames, cameraConfig("right", rate_hz)),
        pairs(left, right, pairing()),
        streamer(pairs, server, clock, std::move(poses), config) {
    std::string error;
    left.start(&error);
    right.start(&error);
    pairs.start();
    streamer.start();
  }
  ~ReplayVideoSource() {
    streamer.stop();
    pairs.stop();
    left.stop();
    right.stop();
  }

 private:
  robot::cameras::ReplayCameraConfig cameraConfig(const char* name, double rate_hz) const {
    robot::cameras::ReplayCameraConfig config;
    config.name = name;
    config.fps = rate_hz;
    config.start_ns = start_ns;  // one instant for both: a triggered pair
    return config;
  }
  static robot::stereo::StereoPairerOptions pairing() {
    robot::stereo::StereoPairerOptions options;
    options.tolerance_ns = 1'000'000;
    return options;
  }
};

}  // namespace telesphere::bench
