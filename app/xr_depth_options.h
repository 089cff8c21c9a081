// SPDX-License-Identifier: MIT
/// @brief What the operator app assumes about the scene's depth (#35), the same options for
///        `telesphere-xr offscreen`, `openxr` and `desktop`: the scene proxy, how the grid meets a
///        depth edge, and how long a new image may wait for the depth of its own pair.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "xr/frame_loop/operator_view.h"

namespace telesphere::app {

struct XrDepthOptions {
  std::string proxy = "fixed";         ///< fixed | radius | grid
  std::string grid_edges = "nearest";  ///< nearest | bilinear (xr/render/eye_view.h)
  double hold_ms = 0.0;                ///< OperatorViewOptions::depth_hold_ms
  int motion_views = 2;                ///< DepthWorkerOptions::motion_views
  bool gpu = false;                    ///< DepthWorkerOptions::gpu
  bool gpu_software = false;           ///< DepthWorkerOptions::gpu_software_ok
};

/// --depth-proxy, --grid-edges, --depth-hold-ms, --depth-motion-views, --depth-gpu on `command`; `until` ends the proxy's help (who
/// may change it while the app runs).
void addXrDepthOptions(CLI::App& command, XrDepthOptions& options, const std::string& until);
/// The depth worker's settings the options give (the motion views, the GPU): every command's
/// operator view and the offline replay take them from here.
xr::frame_loop::DepthWorkerOptions depthWorkerOptions(const XrDepthOptions& options);
/// The proxy, the hold and the motion views into the operator view's options (the grid edges go through
/// render::renderSettingsFromText with the mode and path).
void applyXrDepthOptions(const XrDepthOptions& options, xr::frame_loop::OperatorViewOptions& view);

}  // namespace telesphere::app
