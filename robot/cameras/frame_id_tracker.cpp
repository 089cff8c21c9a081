// SPDX-License-Identifier: MIT
/// @brief FrameIdTracker: frame-id unwrapping and lost-frame counting.
#include "robot/cameras/frame_id_tracker.h"

namespace telesphere::robot::cameras {

FrameIdTracker::Step FrameIdTracker::next(std::uint64_t frame_id) {
  if (frame_id == 0) zero_used_ = true;
  Step step;
  std::uint64_t distance = 0;  // ids from last to this one; 0 = restart
  if (have_last_) {
    if (frame_id > last_id_) {
      distance = frame_id - last_id_;
    } else if (last_id_ <= 0xFFFF && last_id_ - frame_id > 0x8000) {
      distance = (0xFFFF - last_id_) + frame_id + (zero_used_ ? 1 : 0);
    }
    if (distance > max_gap_ + 1) distance = 0;
  }
  if (distance == 0) {
    step.resynced = true;
    sequence_ = started_ ? sequence_ + 1 : frame_id;
  } else {
    step.lost = distance - 1;
    sequence_ += distance;
  }
  have_last_ = true;
  started_ = true;
  last_id_ = frame_id;
  step.sequence = sequence_;
  return step;
}

}  // namespace telesphere::robot::cameras
