// SPDX-License-Identifier: MIT
/// @brief The XR commands' depth options.
#include "app/xr_depth_options.h"

#include "robot/link/depth_proxy.h"
#include "xr/render/eye_view.h"

namespace telesphere::app {

void addXrDepthOptions(CLI::App& command, XrDepthOptions& options, const std::string& until) {
  command
      .add_option("--depth-proxy", options.proxy,
                  "scene proxy: fixed (the sphere of --radius), radius (one radius from the stereo pair's depth) or grid "
                  "(an inverse-depth grid from it; exact and lut paths), " +
                      until)
      ->capture_default_str()
      ->check(CLI::IsMember({"fixed", "radius", "grid"}));
  command.add_option("--grid-edges", options.grid_edges, xr::render::kGridEdgesHelp)
      ->capture_default_str()
      ->check(CLI::IsMember({"nearest", "bilinear"}));
  command
      .add_option("--depth-hold-ms", options.hold_ms,
                  "with radius or grid: a new camera image waits up to this long for the depth of its own pair before "
                  "it is shown (0: at once, with the pair before's depth; an object moving in depth is then placed a "
                  "sweep late)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  command
      .add_option("--depth-motion-views", options.motion_views,
                  "with radius or grid: up to this many of each camera's images from the last 2 s, where the arm has "
                  "moved it 5 mm or more across its optical axis (at most 15 cm) since, join its sweep as more "
                  "baselines (they decide a pattern repeating along the pair's baseline; each costs CPU: "
                  "telesphere-bench depth); 0: the pair alone")
      ->capture_default_str()
      ->check(CLI::Range(0, 4));
  command.add_flag("--depth-gpu", options.gpu,
                   "with radius or grid: the stereo sweep's pair costs on the GPU (a GL 4.5 context of the depth "
                   "thread's own on an EGL device that is a GPU), leaving about a quarter of its CPU time; where there "
                   "is none, the CPU, and the stats say why");
  command.add_flag("--depth-gpu-software", options.gpu_software,
                   "with --depth-gpu: take a software GL (Mesa's llvmpipe) where there is no GPU; it sums on the CPU's "
                   "cores, slower than the CPU path (tests, and checking the GPU path on a machine without one)");
}

xr::frame_loop::DepthWorkerOptions depthWorkerOptions(const XrDepthOptions& options) {
  xr::frame_loop::DepthWorkerOptions depth;
  depth.motion_views = options.motion_views;
  depth.gpu = options.gpu;
  depth.gpu_software_ok = options.gpu_software;
  return depth;
}

void applyXrDepthOptions(const XrDepthOptions& options, xr::frame_loop::OperatorViewOptions& view) {
  view.depth_proxy = *link::parseDepthProxy(options.proxy);  // checked by the option
  view.depth_hold_ms = options.hold_ms;
  view.depth = depthWorkerOptions(options);
}

}  // namespace telesphere::app
