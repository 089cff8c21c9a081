// SPDX-License-Identifier: MIT
/// @brief The operator app without a headset (DESIGN.md §7, issue "operator app"): an EGL
///        surfaceless context, head poses from a trajectory, the same per-frame work as with a
///        headset — newest decoded stereo frame → both eyes rendered → head target sent to the
///        robot — paced at the headset's rate. Writes statistics and, optionally, PNGs of the
///        eyes. Used by tests, the benchmark and the README's demo.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "calib/system_calibration.h"
#include "robot/link/link_endpoints.h"
#include "xr/render/eye_view.h"
#include "xr/frame_loop/head_trajectory.h"
#include "xr/frame_loop/operator_view.h"
#include "xr/frame_loop/paced_output.h"

namespace telesphere::xr::frame_loop {

struct OffscreenOperatorOptions {
  link::LinkEndpoints endpoints;
  PacedOutputOptions display;  ///< rate the loop paces at, eye size and field of view, ipd
  double duration_s = 10.0;           ///< 0: until `stop`
  bool loop_trajectory = true;
  render::RenderSettings render;
  int upload_ring_slots = StereoViewRenderer::kDefaultUploadSlots;  ///< 0: upload from the decoder's memory
  /// When set: eyes_last.png (side by side) at the end, and views.csv with the camera frame and
  /// head pose of each PNG (xr/frame_loop/logged_view.h).
  std::string png_dir;
  int png_every_frames = 0;  ///< > 0: also eyes_NNNNN.png every this many frames
  std::chrono::milliseconds wait_first_frame{10000};  ///< give up when no frame arrives
  /// When set: the projection maps of every truth_every_frames-th frame go there
  /// (ProjectionMapRecorder), for the ground-truth check.
  std::string truth_dir;
  int truth_every_frames = 10;
  bool media_link = false;  ///< frames over the UDP media path (OperatorViewOptions::media_link)
  int media_port = 0;       ///< its port when not base port + 4
  bool media_repair = true;  ///< OperatorViewOptions::media_repair
  bool head_targets_on_zmq = true;  ///< OperatorViewOptions::head_targets_on_zmq
  bool warn_insecure_link = false;  ///< OperatorViewOptions::warn_insecure_link
  link::DepthProxy depth_proxy = link::DepthProxy::kFixed;  ///< OperatorViewOptions::depth_proxy (#35)
  double depth_hold_ms = 0.0;  ///< OperatorViewOptions::depth_hold_ms
  DepthWorkerOptions depth;    ///< OperatorViewOptions::depth (the motion views, the GPU)
};

/// The per-frame core's figures (render ms: both eyes, incl. upload, to glFinish) and the loop's
/// own pacing figures.
struct OffscreenOperatorStats {
  OperatorViewStats view;
  std::uint64_t missed_frames = 0;  ///< display periods missed because the work overran
  double fps = 0;
};

/// Runs the loop; nothing, with the reason in *error, when GL, the calibration or the link do
/// not allow it (or no frame arrived in wait_first_frame).
std::optional<OffscreenOperatorStats> runOffscreenOperator(
    const calib::SystemCalibration& calibration, const HeadTrajectory& trajectory,
    const OffscreenOperatorOptions& options, const std::atomic<bool>& stop, std::string* error);

}  // namespace telesphere::xr::frame_loop
