// SPDX-License-Identifier: MIT
/// @brief runOffscreenOperator: the operator loop on an EGL surfaceless context, paced by the clock.
#include "xr/frame_loop/offscreen_operator.h"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "shaders/egl_context.h"
#include "xr/frame_loop/eyes_png.h"
#include "xr/frame_loop/logged_view.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/frame_loop/operator_view.h"
#include "xr/frame_loop/paced_output.h"
#include "xr/frame_loop/projection_map_recorder.h"

namespace telesphere::xr::frame_loop {

std::optional<OffscreenOperatorStats> runOffscreenOperator(
    const calib::SystemCalibration& calibration, const HeadTrajectory& trajectory,
    const OffscreenOperatorOptions& options, const std::atomic<bool>& stop, std::string* error) {
  if (calibration.cameras.size() != 2) {
    *error = "the calibration needs two cameras";
    return std::nullopt;
  }
  if (!(options.display.rate_hz > 0.0 && options.display.rate_hz <= 1000.0)) {
    *error = "display rate must be in (0, 1000] Hz";
    return std::nullopt;
  }
  auto context = gl::EglContext::createSurfaceless(error);
  if (!context || !context->makeCurrent()) {
    if (error->empty()) *error = "cannot make the EGL context current";
    return std::nullopt;
  }
  OffscreenOutput output(options.display, [&](double display_s) { return trajectory.sample(display_s, options.loop_trajectory); });
  if (!output.complete()) {
    *error = "cannot create " + std::to_string(options.display.eye_width) + "x" +
             std::to_string(options.display.eye_height) + " render targets";
    return std::nullopt;
  }

  OperatorViewOptions view_options;
  view_options.endpoints = options.endpoints;
  view_options.render = options.render;
  view_options.upload_ring_slots = options.upload_ring_slots;
  view_options.media_link = options.media_link;
  view_options.warn_insecure_link = options.warn_insecure_link;
  view_options.media_port = options.media_port;
  view_options.media_repair = options.media_repair;
  view_options.head_targets_on_zmq = options.head_targets_on_zmq;
  view_options.depth_proxy = options.depth_proxy;
  view_options.depth_hold_ms = options.depth_hold_ms;
  view_options.depth = options.depth;
  OperatorView operator_view(calibration, view_options);

  using Clock = std::chrono::steady_clock;
  // Wait for the first decoded frame so a slow robot start does not count as missed frames.
  const auto first_deadline = Clock::now() + options.wait_first_frame;
  while (!operator_view.decoder().waitNewer(0, std::chrono::milliseconds(50)) && !stop.load()) {
    operator_view.keepMediaSession();  // a keyed media path sends nothing before its key
    // The robot's answer to this program's keys does not change by waiting: say it now.
    if (const auto activity = operator_view.client().activity(); activity.refusal_settled) {
      *error = "no stereo frame from the robot at " + options.endpoints.connect(0) + ": " + activity.refused_reason;
      return std::nullopt;
    }
    if (Clock::now() > first_deadline) {
      const std::string refused = operator_view.client().activity().refused_reason;
      // Frames that came but were not shown say why (a codec this build lacks, a stream that
      // never sent the key frame asked for) better than "is it running?".
      const auto decoded = operator_view.decoder().stats();
      std::string dropped;
      for (int r = 0; r < static_cast<int>(video::FrameDropReason::kCount); ++r)
        if (const auto n = decoded.dropped_by_reason[static_cast<std::size_t>(r)]; n > 0)
          dropped += (dropped.empty() ? "" : ", ") + std::to_string(n) + " " +
                     std::string(video::frameDropReasonName(static_cast<video::FrameDropReason>(r)));
      if (const auto* media = operator_view.media(); media && dropped.empty()) {
        const auto m = media->stats().assembler;
        if (m.datagrams > 0)
          dropped = "the media path took " + std::to_string(m.datagrams) + " datagrams and made no frame of them (" +
                    std::to_string(m.frames_malformed) + " malformed, " + std::to_string(m.frames_lost) + " lost)";
      }
      *error = "no stereo frame from the robot at " + options.endpoints.connect(0) + " within " +
               std::to_string(options.wait_first_frame.count()) + " ms (" +
               (!refused.empty()   ? refused
                : !dropped.empty() ? "frames came, none was shown: " + dropped
                                   : std::string("is telesphere-robot running?")) +
               ")";
      return std::nullopt;
    }
  }

  std::unique_ptr<ProjectionMapRecorder> truth;
  if (!options.truth_dir.empty()) {
    truth = ProjectionMapRecorder::open(options.truth_dir, options.display.eye_width, options.display.eye_height, error);
    if (!truth) return std::nullopt;
  }

  if (!options.png_dir.empty()) {
    std::error_code ec;
    std::filesystem::remove(options.png_dir + "/" + kLoggedViewsFile, ec);  // this run's views only
  }
  OperatorLoop loop(operator_view, output);
  // Each PNG with the camera frame and head pose it shows (views.csv), for the replay's check.
  const auto writeEyes = [&](const std::string& png, const DisplayFrame& shown) {
    if (!writeEyesPng(options.png_dir + "/" + png, output.left(), output.right(), error)) return false;
    const auto& frame = operator_view.frame();
    return !frame || appendLoggedView(options.png_dir + "/" + kLoggedViewsFile,
                                      LoggedView{png, frame->frame.sequence(), shown.T_vr_hmd,
                                                 operator_view.settings().image_saturation, operator_view.linkState()},
                                      error);
  };
  const Eigen::Isometry3d T_hmd_eye[2] = {output.T_hmd_eye(0), output.T_hmd_eye(1)};
  const auto t0 = Clock::now();
  while (!stop.load()) {
    if (options.duration_s > 0 && Clock::now() - t0 >= std::chrono::duration<double>(options.duration_s)) break;
    if (!loop.step(error)) return std::nullopt;
    const DisplayFrame& shown = loop.last().frame;
    const std::uint64_t frames = loop.stats().frames;
    // The projection maps are extra work for the check, after the frame's own (not in render_ms).
    if (truth && options.truth_every_frames > 0 && frames % static_cast<std::uint64_t>(options.truth_every_frames) == 0 &&
        !truth->record(operator_view, shown.display_ns, shown.T_vr_hmd, T_hmd_eye, options.display.ipd, shown.views[0], error))
      return std::nullopt;
    const std::string png = options.png_dir.empty() ? "" : everyNthEyesPngName(frames, options.png_every_frames);
    if (!png.empty() && !writeEyes(png, shown)) return std::nullopt;
  }
  OffscreenOperatorStats stats;
  const OperatorLoopStats loop_stats = loop.stats();
  stats.fps = loop_stats.fps;
  stats.missed_frames = loop_stats.missed_frames;
  stats.view = operator_view.stats();
  if (!options.png_dir.empty() && !writeEyes("eyes_last.png", loop.last().frame)) return std::nullopt;
  return stats;
}

}  // namespace telesphere::xr::frame_loop
