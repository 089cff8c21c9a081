// SPDX-License-Identifier: MIT
/// @brief PacedOutput: pacing by a FrameClock, head and eye poses, two eye targets.
#include "xr/frame_loop/paced_output.h"

#include <algorithm>
#include <chrono>

namespace telesphere::xr::frame_loop {

PacedOutput::PacedOutput(const PacedOutputOptions& options, HeadAt head, FrameClock* clock)
    : options_(options),
      head_(std::move(head)),
      clock_(clock != nullptr ? clock : &steady_),
      left_(options.eye_width, options.eye_height),
      right_(options.eye_width, options.eye_height),
      period_ns_(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(1.0 / options.rate_hz))
                     .count()) {
  for (int eye = 0; eye < 2; ++eye) {
    T_hmd_eye_[std::size_t(eye)] = Eigen::Isometry3d::Identity();
    T_hmd_eye_[std::size_t(eye)].translation().x() = (eye == 0 ? -0.5 : 0.5) * options.ipd;
  }
}

void PacedOutput::waitUntilDue() {
  if (due_) return;
  clock_->sleepUntilNs(next_start_ns_);
  due_ = true;
}

bool PacedOutput::frame(const DrawEye& draw, Shown* shown, std::string* error) {
  if (!first_start_ns_) first_start_ns_ = next_start_ns_ = clock_->nowNs();
  waitUntilDue();
  due_ = false;
  const std::int64_t start = next_start_ns_;
  const std::int64_t display = start + period_ns_;  // shown at the next refresh
  DisplayFrame& f = shown->frame;
  f.index = index_++;
  f.display_ns = f.refresh_ns = display;
  f.display_period_ns = period_ns_;
  f.T_vr_hmd = head_(double(display - *first_start_ns_) * 1e-9);
  f.head_valid = true;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    f.T_vr_eye[eye] = f.T_vr_hmd * T_hmd_eye_[eye];
    f.views[eye].fov = options_.fov;
    f.views[eye].width = options_.eye_width;
    f.views[eye].height = options_.eye_height;
  }
  shown->began = true;
  if (!draw(f, 0, left_.framebuffer()) || !draw(f, 1, right_.framebuffer()) || !present(error)) return false;
  const std::int64_t done = clock_->nowNs();
  shown->drawn = true;
  shown->shown_ns = std::max(display, done);
  // The next frame starts at the refresh after this one; an overrun skips refreshes, never bursts.
  next_start_ns_ = start + period_ns_;
  if (done > display) next_start_ns_ += ((done - next_start_ns_) / period_ns_ + 1) * period_ns_;
  return true;
}

bool OffscreenOutput::present(std::string*) {
  glFinish();
  return true;
}

}  // namespace telesphere::xr::frame_loop
