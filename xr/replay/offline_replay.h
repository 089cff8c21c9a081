// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr offscreen --replay FILE`: a recorded session (telesphere-robot --record)
///        rendered offline, deterministically — the same PNGs run after run (issue #18). No link,
///        no wall time: display frames fall on a simulated clock at exactly first + k · period on
///        the recording's time line (its log times, the robot's clock), starting at the first
///        stereo frame; each display frame shows what was logged up to its start — the newest
///        frame (decoded then, synchronously), the newest robot state (mode, radius, nominal
///        mapping, trial), the scene proxy the operator's eyes had (its depth measured again from
///        the recorded pairs, recorded_view.h) and, for the head, the newest recorded head target (what the operator's
///        headset sent) or a head trajectory given instead. Each frame is rendered with the
///        calibration the robot used for it, as the recording attached it, unless one is given
///        to override them. The one operator frame loop (OperatorLoop, OffscreenOutput) draws it
///        on an EGL surfaceless context. With the views a live run logged (views.csv) it renders
///        those instead, each from its own camera frame and head pose, for a check of the replay
///        against what the operator saw.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calib/system_calibration.h"
#include "xr/frame_loop/head_trajectory.h"
#include "xr/frame_loop/logged_view.h"
#include "xr/frame_loop/operator_view.h"
#include "xr/frame_loop/paced_output.h"

namespace telesphere::xr::replay {

struct OfflineReplayOptions {
  std::string recording;       ///< the MCAP file
  frame_loop::PacedOutputOptions display;  ///< display rate, eye size and field of view, ipd
  render::RenderSettings render;       ///< until a recorded state says otherwise
  bool follow_recorded_settings = true;  ///< the recorded mode, radius and scene proxy (off: `render`'s and `depth_proxy` stay)
  /// The scene proxy until the recording says otherwise (#35), and its stereo depth's settings.
  link::DepthProxy depth_proxy = link::DepthProxy::kFixed;
  frame_loop::DepthWorkerOptions depth;
  /// Head poses from this trajectory (time from the first frame) instead of the recorded head targets.
  std::optional<frame_loop::HeadTrajectory> trajectory;
  bool loop_trajectory = true;
  double duration_s = 0;  ///< recording time to render from the first frame; 0: to the end
  std::string png_dir;    ///< when set: eyes_last.png at the end
  int png_every_frames = 0;  ///< > 0: also eyes_NNNNN.png every this many display frames
  /// When set, instead of display frames on the recording's time line: these views of a live run
  /// (its views.csv), each rendered once the recording's frame it shows has been read (with what
  /// was logged before it), its head pose given, into png_dir under the live PNG's name. Not
  /// with a trajectory.
  std::vector<frame_loop::LoggedView> views;
  /// Called after each display frame with the recording seconds rendered and the recording's
  /// length (from its first frame to its last message, or to duration_s), for a progress line.
  std::function<void(double rendered_s, double total_s)> progress;
};

struct OfflineReplayStats {
  frame_loop::OperatorViewStats view;            ///< frames, camera frames shown, render and decode figures
  std::uint64_t recorded_frames = 0;  ///< stereo frames read from the recording
  std::uint64_t head_targets = 0;     ///< recorded head targets taken (0 with a trajectory)
  /// The display frame (counted from 1, as the PNGs are named) from which the robot's nominal pose
  /// was in; 0 when the recording never had one. Before it the view is anchored to the first eye
  /// pose (the stand-in), so any head shows the camera's forward view alike.
  std::uint64_t first_frame_with_nominal = 0;
  std::uint64_t undecodable = 0;      ///< recorded frames whose JPEGs (access units) did not decode
  std::uint64_t awaiting_key_frame = 0;  ///< H.264/HEVC frames passed over until a key frame after a gap
  std::uint64_t replaced_unshown = 0;  ///< recorded frames a newer one replaced within a display period
  std::uint64_t skipped = 0;          ///< messages passed over (RecordingReader::skipped)
  double recording_s = 0;             ///< recording time rendered, from the first frame
  std::uint64_t views_rendered = 0;   ///< of OfflineReplayOptions::views
  /// Views whose camera frame the recording does not hold (their sequence numbers, up to 20).
  std::vector<std::uint64_t> views_missing;
  /// Whose calibration was used: "the recording's, generation 1" (and its changes in
  /// view.calibration_changes), or "given (overrides the recording's)".
  std::string calibration;
};

/// Renders the recording with `given` for every frame, or (nothing given) with the calibrations
/// the recording holds; nothing, with the reason in *error, when the file, GL or the calibration
/// do not allow it (a recording without calibrations needs one given), or the recording holds no
/// complete stereo frame (or no head targets when neither a trajectory nor views are given).
std::optional<OfflineReplayStats> runOfflineReplay(const std::optional<calib::SystemCalibration>& given,
                                                   const OfflineReplayOptions& options,
                                                   const std::atomic<bool>& stop, std::string* error);

}  // namespace telesphere::xr::replay
