// SPDX-License-Identifier: MIT
/// @brief PacedOutput: steady-clock pacing, head and eye poses, two eye targets.
#include "xr/operator/paced_output.h"

#include <algorithm>
#include <thread>

namespace telesphere::xr {
namespace {

std::int64_t steadyNs(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

}  // namespace

PacedOutput::PacedOutput(const PacedOutputOptions& options, HeadAt head)
    : options_(options),
      head_(std::move(head)),
      left_(options.eye_width, options.eye_height),
      right_(options.eye_width, options.eye_height),
      period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options.rate_hz))) {
  for (int eye = 0; eye < 2; ++eye) {
    T_hmd_eye_[std::size_t(eye)] = Eigen::Isometry3d::Identity();
    T_hmd_eye_[std::size_t(eye)].translation().x() = (eye == 0 ? -0.5 : 0.5) * options.ipd;
  }
}

void PacedOutput::waitUntilDue() {
  if (due_) return;
  std::this_thread::sleep_until(next_start_);
  due_ = true;
}

bool PacedOutput::frame(const DrawEye& draw, Shown* shown, std::string* error) {
  if (!first_start_) first_start_ = next_start_ = Clock::now();
  waitUntilDue();
  due_ = false;
  const Clock::time_point start = next_start_;
  const Clock::time_point display = start + period_;  // shown at the next refresh
  DisplayFrame& f = shown->frame;
  f.index = index_++;
  f.display_ns = f.refresh_ns = steadyNs(display);
  f.display_period_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(period_).count();
  f.T_vr_hmd = head_(std::chrono::duration<double>(display - *first_start_).count());
  f.head_valid = true;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    f.T_vr_eye[eye] = f.T_vr_hmd * T_hmd_eye_[eye];
    f.views[eye].fov = options_.fov;
    f.views[eye].width = options_.eye_width;
    f.views[eye].height = options_.eye_height;
  }
  shown->began = true;
  if (!draw(f, 0, left_.framebuffer()) || !draw(f, 1, right_.framebuffer()) || !present(error)) return false;
  const Clock::time_point done = Clock::now();
  shown->drawn = true;
  shown->shown_ns = steadyNs(std::max(display, done));
  // The next frame starts at the refresh after this one; an overrun skips refreshes, never bursts.
  next_start_ = start + period_;
  if (done > display) next_start_ += ((done - next_start_) / period_ + 1) * period_;
  return true;
}

bool OffscreenOutput::present(std::string*) {
  glFinish();
  return true;
}

}  // namespace telesphere::xr
