// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr openxr`: the operator app in a headset (or against Monado). With
///        --calib it shows telesphere-robot's cameras: every frame the HMD pose at the predicted
///        display time goes to the robot as the head target, both eyes are rendered from the
///        newest stereo frame through the nominal mapping, and the mode and sphere radius follow
///        the robot (the console changes them there). With --test-scene it shows the built-in
///        test scene instead (no robot needed). When the runtime goes away it waits up to
///        --reconnect seconds for it to come back and starts a new session.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "app/xr_depth_options.h"
#include "app/xr_video_link_options.h"

namespace telesphere::app {

struct OpenXrCommandOptions {
  std::string calib;        ///< system calibration: frames from the robot
  bool test_scene = false;  ///< the built-in test scene instead of the robot's frames
  std::string host = "127.0.0.1";
  int port = 5760;
  int frames = 0;  ///< 0: until SIGINT or the runtime ends the session
  std::string readback_dir;  ///< every swapchain image as PNG + poses.csv (+ the planes shown)
  std::string out_dir;       ///< stats.json at the end
  std::string mode = "full6d", path = "exact", colour = "auto";
  double radius = 1.0;
  XrDepthOptions depth;  ///< --depth-proxy, --grid-edges, --depth-hold-ms (#35)
  double exit_timeout_s = 5.0;
  double reconnect_s = 30.0;  ///< 0: exit (code 4) when the runtime goes away
  bool mirror = false;        ///< a desktop window showing both eyes
  /// auto: EGL where the runtime offers XR_MNDX_egl_enable (no display needed), else GLX
  /// (Xlib; needs an X display, the window is the drawable); egl; glx.
  std::string binding = "auto";
  VideoLinkOptions link;  ///< frames and head targets: the ZeroMQ link or the media path
};

CLI::App* addOpenXrCommand(CLI::App& app, OpenXrCommandOptions& options);
/// Exit codes: 0 ok, 1 bad arguments or files, 2 no GL context, 3 an OpenXR call or rendering
/// failed, 4 the runtime went away (and did not come back within --reconnect), 5 no runtime.
int runOpenXrCommand(const OpenXrCommandOptions& options);

}  // namespace telesphere::app
