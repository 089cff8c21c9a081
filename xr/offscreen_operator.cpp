// SPDX-License-Identifier: MIT
/// @brief runOffscreenOperator: the paced frame loop on an EGL surfaceless context.
#include "xr/offscreen_operator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "xr/eyes_png.h"
#include "xr/operator_view.h"
#include "xr/projection_map_recorder.h"

namespace telesphere::xr {

std::optional<OffscreenOperatorStats> runOffscreenOperator(
    const calib::SystemCalibration& calibration, const HeadTrajectory& trajectory,
    const OffscreenOperatorOptions& options, const std::atomic<bool>& stop, std::string* error) {
  if (calibration.cameras.size() != 2) {
    *error = "the calibration needs two cameras";
    return std::nullopt;
  }
  if (!(options.rate_hz > 0.0 && options.rate_hz <= 1000.0)) {
    *error = "display rate must be in (0, 1000] Hz";
    return std::nullopt;
  }
  auto context = gl::EglContext::createSurfaceless(error);
  if (!context || !context->makeCurrent()) {
    if (error->empty()) *error = "cannot make the EGL context current";
    return std::nullopt;
  }
  gl::OffscreenTarget left_target(options.eye_width, options.eye_height);
  gl::OffscreenTarget right_target(options.eye_width, options.eye_height);
  if (!left_target.complete() || !right_target.complete()) {
    *error = "cannot create " + std::to_string(options.eye_width) + "x" +
             std::to_string(options.eye_height) + " render targets";
    return std::nullopt;
  }

  OperatorViewOptions view_options;
  view_options.endpoints = options.endpoints;
  view_options.render = options.render;
  view_options.upload_ring_slots = options.upload_ring_slots;
  OperatorView operator_view(calibration, view_options);

  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options.rate_hz));
  const auto to_ns = [](Clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  };

  // Wait for the first decoded frame so a slow robot start does not count as missed frames.
  const auto first_deadline = Clock::now() + options.wait_first_frame;
  while (!operator_view.decoder().newest() && !stop.load()) {
    if (Clock::now() > first_deadline) {
      *error = "no stereo frame from the robot at " + options.endpoints.connect(0) + " within " +
               std::to_string(options.wait_first_frame.count()) + " ms (is telesphere-robot running?)";
      return std::nullopt;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }

  std::unique_ptr<ProjectionMapRecorder> truth;
  if (!options.truth_dir.empty()) {
    truth = ProjectionMapRecorder::open(options.truth_dir, options.eye_width, options.eye_height, error);
    if (!truth) return std::nullopt;
  }

  OffscreenOperatorStats stats;
  std::uint64_t frames = 0;
  Eigen::Isometry3d T_hmd_eye[2];
  for (int eye = 0; eye < 2; ++eye) {
    T_hmd_eye[eye] = Eigen::Isometry3d::Identity();
    T_hmd_eye[eye].translation().x() = (eye == 0 ? -0.5 : 0.5) * options.ipd;
  }
  const auto t0 = Clock::now();
  auto frame_start = t0;
  while (!stop.load()) {
    if (options.duration_s > 0 && frame_start - t0 >= std::chrono::duration<double>(options.duration_s)) break;
    const auto display = frame_start + period;  // shown at the next refresh
    const double display_s = std::chrono::duration<double>(display - t0).count();
    const Eigen::Isometry3d T_vr_hmd = trajectory.sample(display_s, options.loop_trajectory);

    const auto work_start = Clock::now();
    if (!operator_view.beginFrame(T_vr_hmd, to_ns(display), true, error)) return std::nullopt;
    EyeView view;
    view.fov = options.fov;
    view.width = options.eye_width;
    view.height = options.eye_height;
    for (int eye = 0; eye < 2; ++eye) {
      const GLuint fb = eye == 0 ? left_target.framebuffer() : right_target.framebuffer();
      if (!operator_view.renderEye(eye, T_vr_hmd * T_hmd_eye[eye], view, fb, error)) return std::nullopt;
    }
    glFinish();
    const auto work_end = Clock::now();
    // The projection maps are extra work for the check, after the frame's own (not in render_ms).
    if (truth && options.truth_every_frames > 0 && (frames + 1) % static_cast<std::uint64_t>(options.truth_every_frames) == 0 &&
        !truth->record(operator_view, to_ns(display), T_vr_hmd, T_hmd_eye, options.ipd, view, error))
      return std::nullopt;
    ++frames;
    operator_view.endFrame(to_ns(std::max(display, work_end)),
                           std::chrono::duration<double, std::milli>(work_end - work_start).count(),
                           stats.missed_frames);
    if (options.png_every_frames > 0 && !options.png_dir.empty() &&
        frames % static_cast<std::uint64_t>(options.png_every_frames) == 0) {
      char name[64];
      std::snprintf(name, sizeof(name), "/eyes_%05llu.png", static_cast<unsigned long long>(frames));
      if (!writeEyesPng(options.png_dir + name, left_target, right_target, error)) return std::nullopt;
    }

    // Pace: the next frame starts at the refresh; an overrun misses refreshes, never bursts.
    frame_start += period;
    if (work_end > display) {
      const auto behind = (work_end - frame_start) / period + 1;
      stats.missed_frames += static_cast<std::uint64_t>(behind);
      frame_start += behind * period;
    }
    std::this_thread::sleep_until(frame_start);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  stats.fps = seconds > 0 ? double(frames) / seconds : 0.0;
  stats.view = operator_view.stats();
  if (!options.png_dir.empty() && !writeEyesPng(options.png_dir + "/eyes_last.png", left_target, right_target, error))
    return std::nullopt;
  return stats;
}

}  // namespace telesphere::xr
