// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr desktop`: the operator app without a headset, in a window (GLFW on X11,
///        EGL context): the mouse and keyboard move a virtual head (xr/desktop/virtual_head.h), both eyes
///        are rendered from telesphere-robot's newest stereo frame and shown side by side, the
///        head pose goes to the robot as the head target, and N/M/+/− capture the nominal pose,
///        cycle the mode and change the sphere radius through the robot (like the console).
///        For development and demos.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "app/xr_depth_options.h"
#include "app/xr_video_link_options.h"

namespace telesphere::app {

struct DesktopCommandOptions {
  std::string calib;
  std::string host = "127.0.0.1";
  int port = 5760;
  std::string eye_size = "720x800";  ///< render size per eye
  std::string window_size = "1280x720";
  double rate_hz = 60.0;   ///< frames per second the loop paces at (the window does not vsync)
  double duration_s = 0;   ///< 0: until the window closes, Escape or SIGINT
  double ipd = 0.064;      ///< m
  std::string mode = "full6d", path = "exact";
  double radius = 1.0;
  XrDepthOptions depth;  ///< --depth-proxy, --grid-edges, --depth-hold-ms (#35)
  std::string out_dir;     ///< stats.json and eyes_last.png at the end
  VideoLinkOptions link;   ///< frames and head targets: the ZeroMQ link or the media path
};

CLI::App* addDesktopCommand(CLI::App& app, DesktopCommandOptions& options);
/// Exit codes: 0 ok, 1 bad arguments or files, 2 no window (no X display), 3 rendering failed.
int runDesktopCommand(const DesktopCommandOptions& options);

}  // namespace telesphere::app
