// SPDX-License-Identifier: MIT
/// @brief The depth bench's stereo sweeps: sweeping a pair timed on the thread's CPU clock, its
///        error over the tiles the camera sees, the stereo proxies and their figures.
#include "app/bench/depth_bench_stereo.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "app/bench/bench_table.h"
#include "app/bench/cpu_time.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::bench::depth_bench {

using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;

StereoSweeps makeSweeps(const std::string& name, const calib::SystemCalibration& rig, int width, int height,
                        const xr::depth::SphereSweepOptions& options) {
  return {name,
          xr::depth::SphereSweep(rig.cameras[0].camera, width, height, rig.cameras[1].camera, width, height,
                                 rig.T_cam_l_cam_r->inverse(), options),
          xr::depth::SphereSweep(rig.cameras[1].camera, width, height, rig.cameras[0].camera, width, height,
                                 *rig.T_cam_l_cam_r, options)};
}

std::vector<std::pair<int, int>> seenTiles(const xr::render::InverseDepthGrid& grid, const calib::CameraCalibration& camera,
                                           int width, int height) {
  std::vector<std::pair<int, int>> tiles;
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      Eigen::Vector2d px;
      if (camera.camera.project(grid.tileCentre(row, col), px) && px.x() >= 0 && px.y() >= 0 && px.x() <= width - 1 &&
          px.y() <= height - 1)
        tiles.emplace_back(row, col);
    }
  return tiles;
}

StereoDepth sweepPair(StereoSweeps& sweeps, const StereoGrey& pair, int width, int height, const robot::cameras::SceneView& camera,
                      const calib::CameraCalibration& left_camera,
                      const std::array<std::vector<xr::depth::EarlierView>, 2>& earlier, int timed_runs) {
  const xr::depth::GreyImage left{pair.left.data(), width, height, width};
  const xr::depth::GreyImage right{pair.right.data(), width, height, width};
  if (!sweeps.warm) {
    sweeps.left.estimate(left, right);
    sweeps.right.estimate(right, left);
    sweeps.warm = true;
  }
  StereoDepth out;
  xr::depth::SweepResult right_result;
  std::vector<double> ms;
  for (int run = 0; run < std::max(timed_runs, 1); ++run) {
    const double cpu0 = threadCpuSeconds();
    out.left = sweeps.left.estimate(left, right, earlier[0]);
    right_result = sweeps.right.estimate(right, left, earlier[1]);
    ms.push_back(1e3 * (threadCpuSeconds() - cpu0));
  }
  out.ms = quantile(ms, 0.5);
  out.matched = out.left.tiles_matched + right_result.tiles_matched;
  out.decided_by_motion = out.left.tiles_decided_by_motion + right_result.tiles_decided_by_motion;
  out.seen = out.left.tiles_seen + right_result.tiles_seen;
  const xr::render::InverseDepthGrid truth = trueGrid(camera, sweeps.left.options().tile_deg);
  for (const auto& [row, col] : seenTiles(truth, left_camera, width, height))
    out.inverse_depth_error.push_back(std::abs(out.left.inverse_depth.at(row, col) - truth.at(row, col)));
  return out;
}

std::vector<Proxy> stereoProxies(const StereoDepth& depth) {
  std::vector<Proxy> proxies;
  proxies.push_back({"radius", "one radius, sigma " + formatNumber(kCentreSigmaDeg) + " deg, stereo",
                     xr::render::centreWeightedRadius(depth.left.inverse_depth, {0, 0, 1}, kCentreSigmaDeg * kDeg),
                     std::nullopt, {}, {}});
  proxies.push_back({"grid", "grid " + formatNumber(depth.left.inverse_depth.tileDeg()) + " deg, stereo", 0.0,
                     depth.left.inverse_depth, {}, {}});
  return proxies;
}

nlohmann::json stereoFigures(const StereoDepth& depth, const std::vector<Proxy>& proxies) {
  return {{"tiles_matched_fraction", depth.seen ? static_cast<double>(depth.matched) / depth.seen : 0.0},
          {"inverse_depth_error_p50_per_m", quantile(depth.inverse_depth_error, 0.5)},
          {"inverse_depth_error_p90_per_m", quantile(depth.inverse_depth_error, 0.9)},
          {"radius_m", proxies[0].radius_m},
          {"eye_error_moving_fovea_p50_deg_radius", quantile(proxies[0].moving.fovea, 0.5)},
          {"eye_error_moving_p50_deg_grid", quantile(proxies[1].moving.whole, 0.5)},
          {"eye_error_moving_p90_deg_grid", quantile(proxies[1].moving.whole, 0.9)}};
}

}  // namespace telesphere::bench::depth_bench
