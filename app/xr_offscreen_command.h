// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr offscreen`: the operator app without a headset or display (EGL
///        surfaceless): connects to telesphere-robot, plays a head trajectory (CSV, or the built-in
///        demo motion), renders both eyes of the newest stereo frame at the display rate, sends the
///        head targets, prints statistics and writes them (JSON) and the last eye images (PNG).
///        With --replay FILE: a recorded session rendered offline instead, deterministically
///        (xr/replay/offline_replay.h): no robot, the recorded head targets or --trajectory; with
///        --views the PNGs a live run wrote, rendered again from the recording.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "app/xr_depth_options.h"
#include "app/xr_video_link_options.h"

namespace telesphere::app {

struct OffscreenCommandOptions {
  std::string calib;
  std::string host = "127.0.0.1";
  int port = 5760;
  std::string trajectory;  ///< CSV; empty: the built-in demo motion
  std::string eye_size = "1440x1600";
  double rate_hz = 90.0;
  double duration_s = -1;  ///< < 0: 10 s live, the whole recording with --replay
  std::string mode = "full6d";
  std::string path = "exact";
  double radius = 1.0;
  XrDepthOptions depth;  ///< --depth-proxy, --grid-edges, --depth-hold-ms (#35)
  std::string out_dir;  ///< stats.json and eyes_last.png
  int png_every = 0;
  double wait_s = 10.0;
  std::string truth_dir;  ///< projection maps for the ground-truth check
  int truth_every = 10;
  std::string replay;  ///< a recording (MCAP) to render offline instead of the robot
  std::string views;   ///< with replay: a live run's views.csv, rendered instead of display frames
  VideoLinkOptions link;  ///< frames and head targets: the ZeroMQ link or the media path
};

CLI::App* addOffscreenCommand(CLI::App& app, OffscreenCommandOptions& options);
/// Exit codes: 0 ok, 1 bad arguments or files, 2 no GL context or no robot, 3 rendering failed.
int runOffscreenCommand(const OffscreenCommandOptions& options);

}  // namespace telesphere::app
