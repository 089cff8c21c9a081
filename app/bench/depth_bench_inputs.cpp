// SPDX-License-Identifier: MIT
/// @brief The depth bench's harder inputs and the arm's motion as a second baseline.
#include "app/bench/depth_bench_inputs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/bench/bench_table.h"
#include "app/bench/prerendered_frames.h"
#include "robot/video/jpeg_encoder.h"
#include "xr/depth/box_downscale.h"
#include "xr/video/jpeg_decoder.h"

namespace telesphere::bench::depth_bench {

using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;
using Eigen::Vector3d;

StereoGrey degradeAndShrink(const StereoGrey& capture, int width, int height, int factor, const InputVariant& v,
                            std::uint32_t seed) {
  StereoGrey out;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, v.noise_grey > 0 ? v.noise_grey : 1.0);
  robot::video::JpegEncoder encoder;
  xr::video::JpegDecoder decoder;
  for (int side = 0; side < 2; ++side) {
    std::vector<std::uint8_t> grey = side == 0 ? capture.left : capture.right;
    if (v.noise_grey > 0)
      for (std::uint8_t& g : grey) g = static_cast<std::uint8_t>(std::clamp(std::lround(g + noise(rng)), 0L, 255L));
    if (v.jpeg_quality > 0) {
      std::vector<std::uint8_t> jpeg;
      std::string error;
      robot::video::JpegSettings settings;
      settings.quality = v.jpeg_quality;
      if (!encoder.encodeGray(grey.data(), width, height, width, settings, jpeg, &error)) throw std::runtime_error("depth: " + error);
      xr::render::YuvPlanes planes;
      if (decoder.decode(jpeg, width, height, 16384, planes, &error) != xr::video::JpegDecodeError::kNone)
        throw std::runtime_error("depth: " + error);
      grey.assign(planes.yPlane().begin(), planes.yPlane().end());
    }
    int w = 0, h = 0;
    xr::depth::boxDownscale(grey, width, height, width, factor, side == 0 ? out.left : out.right, &w, &h);
  }
  return out;
}

nlohmann::json runHarderInputs(const BenchContext& ctx, StereoSweeps& sweeps, const calib::CameraCalibration& left_camera,
                               int depth_width, int depth_height) {
  const int factor = ctx.quick ? 2 : 4;  // a 1080p capture (960x540 quick) shrunk to the sweep's size
  const int capture_width = depth_width * factor, capture_height = depth_height * factor;
  const calib::SystemCalibration capture_rig = simulatedRig(capture_width, capture_height);
  const int rays = ctx.quick ? 21 : 61;
  std::vector<InputVariant> variants = {{"clean", 0, 0, {0, 0, 0}},
                                        {"JPEG q90 (the link's default)", 90, 0, {0, 0, 0}},
                                        {"JPEG q50", 50, 0, {0, 0, 0}},
                                        {"noise sigma 4 grey", 0, 4, {0, 0, 0}},
                                        {"noise sigma 12 grey + JPEG q90", 90, 12, {0, 0, 0}},
                                        {"calibration off 0.1 deg about x (vertical)", 0, 0, {0.1, 0, 0}},
                                        {"calibration off 0.1 deg about y (along the baseline)", 0, 0, {0, 0.1, 0}},
                                        {"calibration off 0.1 deg about z (roll)", 0, 0, {0, 0, 0.1}}};
  struct NamedScene {
    std::string name;
    SyntheticScene scene;
  };
  const std::vector<NamedScene> scenes = {{"near objects at 0.5 m", makeScene(0.5)}, {"stripes 2 cm apart at 0.8 m", makeStripesScene()}};
  auto& out = ctx.out;
  out << "\nHarder stereo inputs: captured at " << capture_width << "x" << capture_height << ", degraded there, box-filtered by "
      << factor << " to " << depth_width << "x" << depth_height << " (as the operator app does); eye errors moving, " << rays << "x"
      << rays << " rays\n";
  Table table({"scene", "input", "tiles matched %", "inv depth err p50 1/m", "p90", "radius m", "radius fovea moving p50 deg",
               "grid moving p50 deg", "grid moving p90"});
  nlohmann::json rows = nlohmann::json::array();
  std::uint32_t seed = 1;
  for (const NamedScene& named : scenes) {
    const SceneView camera = named.scene.view(0, Eigen::Isometry3d::Identity());
    std::optional<StereoGrey> nominal;  // the capture without a rig error, shared by the other variants
    for (const InputVariant& v : variants) {
      StereoGrey capture;
      if (v.rig_error_deg.isZero()) {
        if (!nominal) nominal = renderPair(named.scene, capture_rig, capture_width, capture_height, 1);
        capture = *nominal;
      } else {
        const Vector3d r = v.rig_error_deg * kDeg;
        Eigen::Isometry3d T_error = Eigen::Isometry3d::Identity();
        T_error.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
        capture = renderPair(named.scene, capture_rig, capture_width, capture_height, 1, T_error);
      }
      const StereoGrey pair = degradeAndShrink(capture, capture_width, capture_height, factor, v, seed++);
      const StereoDepth depth = sweepPair(sweeps, pair, depth_width, depth_height, camera, left_camera);
      std::vector<Proxy> proxies = stereoProxies(depth);
      evaluateEyeErrors(named.scene, camera, proxies, rays, false);
      const double matched = depth.seen ? 100.0 * depth.matched / depth.seen : 0.0;
      table.addRow({named.name, v.name, formatNumber(matched), formatNumber(quantile(depth.inverse_depth_error, 0.5)),
                    formatNumber(quantile(depth.inverse_depth_error, 0.9)), formatNumber(proxies[0].radius_m),
                    formatNumber(quantile(proxies[0].moving.fovea, 0.5)),
                    formatNumber(quantile(proxies[1].moving.whole, 0.5)), formatNumber(quantile(proxies[1].moving.whole, 0.9))});
      nlohmann::json row = stereoFigures(depth, proxies);
      row.update({{"scene", named.name},
                  {"input", v.name},
                  {"jpeg_quality", v.jpeg_quality},
                  {"noise_grey", v.noise_grey},
                  {"rig_error_deg", {v.rig_error_deg.x(), v.rig_error_deg.y(), v.rig_error_deg.z()}}});
      rows.push_back(row);
    }
  }
  table.print(out);
  return rows;
}

nlohmann::json runMotionBaselines(const BenchContext& ctx, StereoSweeps& sweeps, const calib::SystemCalibration& rig, int width,
                                  int height) {
  struct Motion {
    std::string name;
    std::vector<Vector3d> p_world_rig;  // the rig's earlier positions (the left camera's centre; now at the origin)
  };
  const std::vector<Motion> motions = {{"none (the pair alone)", {}},
                                       {"1 cm left", {{-0.01, 0.01, 0.0}}},
                                       {"5 cm left", {{-0.05, 0.01, 0.0}}},
                                       {"5 and 1 cm left", {{-0.05, 0.01, 0.0}, {-0.01, 0.01, 0.0}}},
                                       {"6 and 2 cm up and right", {{0.042, -0.042, 0.0}, {0.014, -0.014, 0.0}}},
                                       {"5 and 1 cm forward", {{0.0, 0.0, 0.05}, {0.0, 0.0, 0.01}}},
                                       {"3 cm down (along the stripes)", {{0.0, 0.03, 0.0}}}};
  struct NamedScene {
    std::string name;
    SyntheticScene scene;
  };
  const std::vector<NamedScene> scenes = {{"stripes 2 cm apart at 0.8 m", makeStripesScene()}, {"near objects at 0.5 m", makeScene(0.5)}};
  const int rays = ctx.quick ? 21 : 61;
  auto& out = ctx.out;
  out << "\nA second baseline from the arm's motion: each camera's images from the rig's earlier positions (the left camera 1 cm "
         "lower too where it moves sideways), swept with the pair now; eye errors moving, "
      << rays << "x" << rays << " rays\n";
  Table table({"scene", "earlier rig positions", "ms/pair (CPU, median of " + std::to_string(kTimedRuns) + " runs)", "tiles matched %", "decided by the views", "inv depth err p50 1/m",
               "p90", "radius m", "radius fovea moving p50 deg", "grid moving p50 deg", "grid moving p90"});
  nlohmann::json rows = nlohmann::json::array();
  const Eigen::Isometry3d& T_l_r = *rig.T_cam_l_cam_r;
  for (const NamedScene& named : scenes) {
    const SceneView camera = named.scene.view(0, Eigen::Isometry3d::Identity());
    const StereoGrey pair = renderPair(named.scene, rig, width, height, 2);
    // Each earlier rig position rendered once (several motions share one); a deque keeps the
    // images where they are while more are added.
    std::deque<std::pair<Vector3d, StereoGrey>> rendered;
    const auto renderedAt = [&](const Vector3d& p) -> const StereoGrey& {
      for (const auto& [at, grey] : rendered)
        if (at == p) return grey;
      return rendered.emplace_back(p, renderPair(named.scene, rig, width, height, 2, Eigen::Isometry3d::Identity(),
                                                 Eigen::Isometry3d(Eigen::Translation3d(p))))
          .second;
    };
    for (const Motion& motion : motions) {
      std::array<std::vector<xr::depth::EarlierView>, 2> earlier;
      for (const Vector3d& p : motion.p_world_rig) {
        const StereoGrey& view = renderedAt(p);
        const Eigen::Isometry3d T_world_rig{Eigen::Translation3d(p)};
        for (int side = 0; side < 2; ++side) {
          // The camera now is at T_rig_cam (the rig at the origin), then at T_world_rig · T_rig_cam.
          const Eigen::Isometry3d T_rig_cam = side == 0 ? Eigen::Isometry3d::Identity() : T_l_r;
          earlier[side].push_back({{(side == 0 ? view.left : view.right).data(), width, height, width},
                                   (T_world_rig * T_rig_cam).inverse() * T_rig_cam});
        }
      }
      const StereoDepth depth = sweepPair(sweeps, pair, width, height, camera, rig.cameras[0], earlier, kTimedRuns);
      std::vector<Proxy> proxies = stereoProxies(depth);
      evaluateEyeErrors(named.scene, camera, proxies, rays, false);
      const double matched = depth.seen ? 100.0 * depth.matched / depth.seen : 0.0;
      table.addRow({named.name, motion.name, formatNumber(depth.ms), formatNumber(matched), std::to_string(depth.decided_by_motion),
                    formatNumber(quantile(depth.inverse_depth_error, 0.5)), formatNumber(quantile(depth.inverse_depth_error, 0.9)),
                    formatNumber(proxies[0].radius_m), formatNumber(quantile(proxies[0].moving.fovea, 0.5)),
                    formatNumber(quantile(proxies[1].moving.whole, 0.5)), formatNumber(quantile(proxies[1].moving.whole, 0.9))});
      nlohmann::json positions = nlohmann::json::array();
      for (const Vector3d& p : motion.p_world_rig) positions.push_back({p.x(), p.y(), p.z()});
      nlohmann::json row = stereoFigures(depth, proxies);
      row.update({{"scene", named.name},
                  {"earlier", motion.name},
                  {"earlier_rig_positions_m", positions},
                  {"depth_ms_per_pair", depth.ms},
                  {"tiles_decided_by_motion", depth.decided_by_motion}});
      rows.push_back(row);
    }
  }
  table.print(out);
  return rows;
}

}  // namespace telesphere::bench::depth_bench
