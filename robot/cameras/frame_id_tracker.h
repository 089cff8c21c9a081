// SPDX-License-Identifier: MIT
/// @brief FrameIdTracker: turns a camera's frame ids (GigE Vision 16-bit block ids that wrap, or
///        64-bit ids) into one increasing sequence and counts the frames lost in between.
#pragma once

#include <cstdint>

namespace telesphere::robot::cameras {

/// Feeds on frame ids in arrival order (AravisCamera feeds the complete frames only and subtracts
/// the incomplete buffers it dropped in between from `lost`).
///
/// - id = last + 1: in order. id > last + 1: the ids between are lost (never delivered at all).
/// - A 16-bit wrap (last ≤ 0xFFFF, id < last by more than 0x8000): GigE Vision 1.x block ids run
///   1..65535 and skip 0; a camera seen to use id 0 is taken to count 0..65535.
/// - Any other step back, or a step forward by more than `max_gap`, is a restart of the camera's
///   counter (acquisition restarted, camera re-opened): the sequence goes on, nothing is counted.
/// The sequence is the unwrapped id: it grows by the id distance, so gaps in it are lost frames.
class FrameIdTracker {
 public:
  struct Step {
    std::uint64_t sequence = 0;  ///< unwrapped id of this frame
    std::uint64_t lost = 0;      ///< frames lost just before this one
    bool resynced = false;       ///< the counter restarted (or this is the first frame)
  };

  explicit FrameIdTracker(std::uint64_t max_gap = 1000) : max_gap_(max_gap) {}

  Step next(std::uint64_t frame_id);

  /// Forgets the last id (the next one starts a new run, counted as a resync).
  void reset() { have_last_ = false; }

 private:
  std::uint64_t max_gap_;
  bool have_last_ = false;
  bool started_ = false;
  bool zero_used_ = false;
  std::uint64_t last_id_ = 0;
  std::uint64_t sequence_ = 0;
};

}  // namespace telesphere::robot::cameras
