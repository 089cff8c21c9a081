// SPDX-License-Identifier: MIT
/// @brief OperatorLoop: one display frame through the view and the output; missed periods.
#include "xr/frame_loop/operator_loop.h"


namespace telesphere::xr::frame_loop {

std::uint64_t skippedPeriods(std::int64_t previous_display_ns, std::int64_t display_ns, std::int64_t period_ns) {
  if (previous_display_ns == 0 || period_ns <= 0 || display_ns <= previous_display_ns) return 0;
  const std::int64_t periods = (display_ns - previous_display_ns + period_ns / 2) / period_ns;
  return periods > 1 ? std::uint64_t(periods - 1) : 0;
}

bool OperatorLoop::step(std::string* error) {
  if (!first_step_) first_step_ = Clock::now();
  Clock::time_point work_start;
  bool began_view = false;
  const DrawEye draw = [&](const DisplayFrame& frame, int eye, GLuint framebuffer) {
    if (!began_view) {  // the frame's work starts with the head target, at the first eye
      work_start = Clock::now();
      if (!scene_.beginFrame(frame.T_vr_hmd, frame.display_ns, frame.head_valid, error)) return false;
      began_view = true;
    }
    return scene_.renderEye(eye, frame.T_vr_eye[std::size_t(eye)], frame.views[std::size_t(eye)], framebuffer, error);
  };
  OperatorOutput::Shown shown;
  const bool ok = output_.frame(draw, &shown, error);
  last_ = shown;
  if (!ok) return false;
  if (!shown.began) return true;
  stats_.missed_frames += skippedPeriods(last_refresh_ns_, shown.frame.refresh_ns, shown.frame.display_period_ns);
  last_refresh_ns_ = shown.frame.refresh_ns;
  if (shown.drawn && began_view) {
    ++stats_.frames;
    scene_.endFrame(shown.shown_ns, std::chrono::duration<double, std::milli>(Clock::now() - work_start).count(),
                   stats_.missed_frames);
  }
  return true;
}

OperatorLoopStats OperatorLoop::stats() const {
  OperatorLoopStats s = stats_;
  const double seconds = first_step_ ? std::chrono::duration<double>(Clock::now() - *first_step_).count() : 0.0;
  s.fps = seconds > 0 ? double(s.frames) / seconds : 0.0;
  return s;
}

}  // namespace telesphere::xr::frame_loop
