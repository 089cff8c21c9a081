// SPDX-License-Identifier: MIT
/// @brief A small live view of both cameras for the console (DESIGN.md §7), next to the 2×4K
///        stream: the video path offers every stereo pair it sent (no copy: the pixels are
///        shared); a thread of its own takes the newest one at most `rate_hz` times a second,
///        box-filters both images down to at most `max_width` pixels wide, encodes them as small
///        JPEGs and publishes them on the link's state channel. The video path never waits for
///        it: a pair offered while one is being encoded replaces the one waiting.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "robot/clock/clock.h"
#include "robot/link/link_server.h"
#include "robot/stereo/stereo_pairer.h"

namespace telesphere::robot::video {

struct PreviewOptions {
  int max_width = 320;   ///< px per image
  double rate_hz = 5.0;  ///< previews per second at most
  int quality = 70;      ///< JPEG quality
};

/// An image reduced for the preview: packed RGB8 (3 channels) or grey (1), no row padding.
struct PreviewImage {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> pixels;
};

/// Reduces an RGB8 or Mono8 frame by the smallest integer factor k that makes it at most
/// `max_width` wide (k = ceil(width / max_width)): each output pixel is the rounded mean of a
/// k×k block; a last partial row or column of blocks is dropped. A Bayer mosaic (#34: cameras
/// send their raw mosaic) becomes RGB with k rounded up to even, each colour the rounded mean of
/// its samples in the block. Nothing for empty frames or max_width < 1.
std::optional<PreviewImage> reduceForPreview(const cameras::CameraFrame& frame, int max_width);

class PreviewStreamer {
 public:
  PreviewStreamer(link::LinkServer& server, const PreviewOptions& options = {});
  ~PreviewStreamer();
  PreviewStreamer(const PreviewStreamer&) = delete;
  PreviewStreamer& operator=(const PreviewStreamer&) = delete;

  void start();
  void stop();

  /// Hands over the pair sent as stereo frame `sequence` (latest wins; never blocks).
  void offer(const stereo::StereoFrame& pair, std::uint64_t sequence);

  /// Reduces, encodes and publishes one pair now (what the thread does); false with the reason.
  bool publish(const stereo::StereoFrame& pair, std::uint64_t sequence, std::string* error);

  std::uint64_t published() const { return published_; }

 private:
  void run();

  link::LinkServer& server_;
  PreviewOptions options_;
  std::mutex mutex_;
  std::condition_variable offered_;
  std::optional<std::pair<stereo::StereoFrame, std::uint64_t>> slot_;
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> published_{0};
  std::thread thread_;
};

}  // namespace telesphere::robot::video
