// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench depth` (#35): what each depth proxy leaves of the operator's eye-image
///        error when the eye is away from the camera (at rest: 5 mm; moving: 6 cm, the experiments'
///        moving p50 at r = 1 m), on synthetic rooms with near objects at `--scene-depth-m`. Each
///        eye ray shows the scene point the camera sees through the proxy's point on that ray;
///        the error is the angle between the eye ray and the direction from the eye to that
///        point. Eye pixels whose true point the camera cannot see (disoccluded) are counted apart.
///        Each proxy twice: with the scene's true depth (an oracle: what the representation can
///        reach) and with the depth the sphere sweep (xr/depth/sphere_sweep.h) finds in the
///        synthetic stereo pair rendered through the simulated 195° lenses, 64 mm apart; and the
///        sweep's speed against its accuracy for a few settings; harder inputs (the robot's JPEG,
///        sensor noise, a 0.1° stereo calibration error, a repetitive pattern); an object
///        approaching through the temporal filter, with the grid of the image shown and of the
///        sweep before it.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/cpu_time.h"
#include "app/bench/depth_bench_approach.h"
#include "app/bench/depth_bench_gpu.h"
#include "app/bench/depth_bench_inputs.h"
#include "app/bench/depth_bench_scenes.h"
#include "app/bench/depth_bench_stereo.h"
#include "app/bench/depth_eye_errors.h"
#include "app/bench/prerendered_frames.h"
#include "robot/clock/clock.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/stereo/stereo_still.h"
#include "robot/video/jpeg_encoder.h"
#include "xr/depth/box_downscale.h"
#include "xr/depth/inverse_depth_filter.h"
#include "xr/depth/sphere_sweep.h"
#include "xr/render/depth_proxy.h"
#include "xr/video/jpeg_decoder.h"

namespace telesphere::bench {
namespace {

using namespace depth_bench;

using Eigen::Vector3d;
using robot::cameras::SceneHit;
using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;

double& sceneDepthOption() {
  static double depth_m = 0;
  return depth_m;
}

/// One way of meeting the grid proxy: how it takes a depth edge and how each eye ray finds it.
struct GridSetting {
  std::string name;
  double edge_slope_per_m_per_deg = xr::render::kGridEdgeSlopePerMPerDeg;
  double march_step_tiles = xr::render::kGridMarchStepTiles;
  xr::render::GridEdgeTile edge_tile = xr::render::GridEdgeTile::kClosest;
};

/// The grid proxy (4° tiles) under each of `settings`, with the sweep's grid and the true one; per
/// setting the worst scene of each column, moving, `rays` × `rays` eye rays, and the grid reads an
/// eye ray takes (mean and p99 over the scene with the most).
nlohmann::json runGridKnob(const BenchContext& ctx, const std::string& title, const std::string& column,
                           const std::vector<GridSetting>& settings, const std::vector<SyntheticScene>& scenes,
                           const std::vector<xr::render::InverseDepthGrid>& stereo_grids, int rays) {
  Table table({column, "depth", "moving p50 deg", "p90", "p99", "fovea p50", "fovea p90", "objects p90", "objects p99",
               "reads/ray mean", "p99"});
  std::vector<xr::render::InverseDepthGrid> oracle_grids;  // once per scene, for every setting
  for (const SyntheticScene& scene : scenes) oracle_grids.push_back(trueGrid(scene.view(0, Eigen::Isometry3d::Identity()), 4.0));
  nlohmann::json rows = nlohmann::json::array();
  for (const bool oracle : {false, true})
    for (const GridSetting& setting : settings) {
      double p50 = 0, p90 = 0, p99 = 0, fovea_p50 = 0, fovea_p90 = 0, objects_p90 = 0, objects_p99 = 0, reads_mean = 0,
             reads_p99 = 0;
      for (std::size_t i = 0; i < scenes.size(); ++i) {
        const SceneView camera = scenes[i].view(0, Eigen::Isometry3d::Identity());
        std::vector<Proxy> proxies = {{"grid", "", 0.0, oracle ? oracle_grids[i] : stereo_grids[i], {}, {}}};
        proxies[0].edge_slope_per_m_per_deg = setting.edge_slope_per_m_per_deg;
        proxies[0].march_step_tiles = setting.march_step_tiles;
        proxies[0].edge_tile = setting.edge_tile;
        evaluateEyeErrors(scenes[i], camera, proxies, rays, false);
        const ErrorSet& e = proxies[0].moving;
        p50 = std::max(p50, quantile(e.whole, 0.5));
        p90 = std::max(p90, quantile(e.whole, 0.9));
        p99 = std::max(p99, quantile(e.whole, 0.99));
        fovea_p50 = std::max(fovea_p50, quantile(e.fovea, 0.5));
        fovea_p90 = std::max(fovea_p90, quantile(e.fovea, 0.9));
        if (!e.objects.empty()) {
          objects_p90 = std::max(objects_p90, quantile(e.objects, 0.9));
          objects_p99 = std::max(objects_p99, quantile(e.objects, 0.99));
        }
        const std::vector<int>& reads = proxies[0].lookups;
        if (!reads.empty()) {
          double sum = 0;
          for (int r : reads) sum += r;
          reads_mean = std::max(reads_mean, sum / static_cast<double>(reads.size()));
          reads_p99 = std::max(reads_p99, quantile(std::vector<double>(reads.begin(), reads.end()), 0.99));
        }
      }
      table.addRow({setting.name, oracle ? "oracle" : "stereo", formatNumber(p50), formatNumber(p90), formatNumber(p99),
                    formatNumber(fovea_p50), formatNumber(fovea_p90), formatNumber(objects_p90), formatNumber(objects_p99),
                    formatNumber(reads_mean), formatNumber(reads_p99)});
      const auto finiteOrNull = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
      rows.push_back({{"setting", setting.name},
                      {"edge_jump_per_m_at_4deg", finiteOrNull(4.0 * setting.edge_slope_per_m_per_deg)},
                      {"march_step_tiles", finiteOrNull(setting.march_step_tiles)},
                      {"edge_tile", setting.edge_tile == xr::render::GridEdgeTile::kClosest ? "closest" : "nearest depth"},
                      {"depth", oracle ? "oracle" : "stereo"},
                      {"eye_error_moving_p50_deg_grid", p50},
                      {"eye_error_moving_p90_deg_grid", p90},
                      {"eye_error_moving_p99_deg_grid", p99},
                      {"eye_error_moving_fovea_p50_deg_grid", fovea_p50},
                      {"eye_error_moving_fovea_p90_deg_grid", fovea_p90},
                      {"eye_error_moving_objects_p90_deg_grid", objects_p90},
                      {"eye_error_moving_objects_p99_deg_grid", objects_p99},
                      {"grid_reads_per_ray_mean", reads_mean},
                      {"grid_reads_per_ray_p99", reads_p99}});
    }
  ctx.out << "\n" << title << " (4 deg tiles; worst scene of each column; eye errors moving, " << rays << "x" << rays
          << " rays; grid reads per eye ray):\n";
  table.print(ctx.out);
  return rows;
}

/// The grid proxy at depth edges both ways: bilinear everywhere against one of the four tiles
/// where they span more than a jump (xr::render::kGridEdgeSlopePerMPerDeg × 4°, half and twice it):
/// the closest, or the nearest depth.
nlohmann::json runEdgeKnob(const BenchContext& ctx, const std::vector<SyntheticScene>& scenes,
                           const std::vector<xr::render::InverseDepthGrid>& stereo_grids, int rays) {
  const double k = xr::render::kGridEdgeSlopePerMPerDeg, march = xr::render::kGridMarchStepTiles;
  constexpr auto kNearestDepth = xr::render::GridEdgeTile::kNearestDepth;
  const std::vector<GridSetting> settings = {{"bilinear everywhere", std::numeric_limits<double>::infinity()},
                                             {"closest above " + formatNumber(2 * k) + " 1/m (half)", 0.5 * k},
                                             {"closest above " + formatNumber(4 * k) + " 1/m (default)", k},
                                             {"closest above " + formatNumber(8 * k) + " 1/m (twice)", 2 * k},
                                             {"nearest depth above " + formatNumber(4 * k) + " 1/m", k, march, kNearestDepth}};
  return runGridKnob(ctx, "The grid at depth edges", "grid at depth edges", settings, scenes, stereo_grids, rays);
}

/// How each eye ray finds the grid: fixed-point steps from its own direction (before the march)
/// against marches of 1, 1/2 (default) and 1/4 tile a step to the first crossing, each with the
/// tile it takes at an edge.
nlohmann::json runMarchKnob(const BenchContext& ctx, const std::vector<SyntheticScene>& scenes,
                            const std::vector<xr::render::InverseDepthGrid>& stereo_grids, int rays) {
  const double k = xr::render::kGridEdgeSlopePerMPerDeg, inf = std::numeric_limits<double>::infinity();
  constexpr auto kNearestDepth = xr::render::GridEdgeTile::kNearestDepth, kClosest = xr::render::GridEdgeTile::kClosest;
  const std::vector<GridSetting> settings = {{"fixed-point, nearest depth at edges (before)", k, inf, kNearestDepth},
                                             {"fixed-point, closest tile at edges", k, inf, kClosest},
                                             {"march 1 tile a step, closest", k, 1.0, kClosest},
                                             {"march 1/2 tile a step, closest (default)", k, 0.5, kClosest},
                                             {"march 1/4 tile a step, closest", k, 0.25, kClosest},
                                             {"march 1/2 tile, nearest depth at edges", k, 0.5, kNearestDepth}};
  return runGridKnob(ctx, "How an eye ray finds the grid", "grid intersection", settings, scenes, stereo_grids, rays);
}

nlohmann::json runDepth(const BenchContext& ctx) {
  std::vector<double> depths = ctx.quick ? std::vector<double>{0.3, 1.5} : std::vector<double>{0.3, 0.5, 0.8, 1.5, 3.0, 10.0};
  if (sceneDepthOption() > 0) depths = {sceneDepthOption()};
  const int rays = ctx.quick ? 41 : 121;     // per side of the eye image
  std::vector<double> scene_depths = {0.0};  // the room alone first
  scene_depths.insert(scene_depths.end(), depths.begin(), depths.end());

  // The stereo rig at the sweep's working resolution (the 4K lens scaled; the renderer's 4K
  // images would be box-filtered down to it), rendered with 2 × 2 rays a pixel.
  const int depth_width = 480, depth_height = 270;
  const calib::SystemCalibration rig = simulatedRig(depth_width, depth_height);
  const xr::depth::SphereSweepOptions sweep_options;
  const auto tables_t0 = std::chrono::steady_clock::now();
  StereoSweeps sweeps = makeSweeps("default", rig, depth_width, depth_height, sweep_options);
  const double tables_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tables_t0).count();

  auto& out = ctx.out;
  out << "depth: sphere sweep on " << depth_width << "x" << depth_height << " grey pairs (195 deg lenses, 64 mm apart), "
      << sweep_options.tile_deg << " deg tiles, " << sweep_options.hypotheses << " inverse depths to "
      << sweep_options.min_depth_m << " m, " << sweep_options.samples_per_side << "x" << sweep_options.samples_per_side
      << " samples a tile; tables " << formatNumber(sweeps.left.tableBytes() / 1e6) << " MB a camera, built in "
      << formatNumber(tables_s) << " s for both\n";
  out << "depth: eye-image error per proxy; eye " << 2 * kEyeHalfFovDeg << " deg square, " << rays << "x" << rays
      << " rays, fovea +-" << kFoveaDeg << " deg; eye offset at rest " << kRestOffsetM * 1e3 << " mm, moving "
      << kMovingOffsetM * 1e3 << " mm (" << offsetDirections().size() << " directions)\n";

  nlohmann::json scenes = nlohmann::json::array();
  nlohmann::json worst = nlohmann::json::object();
  const auto keepWorst = [&](const std::string& key, double v) {
    if (!worst.contains(key) || v > worst[key].get<double>()) worst[key] = v;
  };
  std::vector<SyntheticScene> built;
  std::vector<StereoGrey> pairs;
  std::vector<xr::render::InverseDepthGrid> stereo_grids;  // the left camera's, per scene
  for (double near_m : scene_depths) {
    const SyntheticScene& scene = built.emplace_back(makeScene(near_m));
    const SceneView camera = scene.view(0, Eigen::Isometry3d::Identity());
    const StereoGrey& pair = pairs.emplace_back(renderPair(scene, rig, depth_width, depth_height, 2));
    const auto t0 = std::chrono::steady_clock::now();
    const StereoDepth stereo = sweepPair(sweeps, pair, depth_width, depth_height, camera, rig.cameras[0], {}, kTimedRuns);
    stereo_grids.push_back(stereo.left.inverse_depth);

    std::vector<Proxy> proxies;
    proxies.push_back({"fixed", "fixed sphere r = 1 m", 1.0, std::nullopt, {}, {}});
    for (Proxy& p : stereoProxies(stereo)) proxies.push_back(std::move(p));
    const xr::render::InverseDepthGrid truth_2deg = trueGrid(camera, 2.0);
    for (double sigma_deg : {kCentreSigmaDeg, 2.0 * kCentreSigmaDeg}) {
      const double radius = xr::render::centreWeightedRadius(truth_2deg, {0, 0, 1}, sigma_deg * kDeg);
      proxies.push_back({sigma_deg == kCentreSigmaDeg ? "radius_oracle" : "radius_oracle_sigma_" + formatNumber(sigma_deg) + "deg",
                         "one radius, sigma " + formatNumber(sigma_deg) + " deg, oracle", radius, std::nullopt, {}, {}});
    }
    for (double tile : {10.0, 4.0, 2.0}) {
      const std::string t = formatNumber(tile);
      proxies.push_back({tile == 4.0 ? "grid_oracle" : "grid_oracle_" + t + "deg", "grid " + t + " deg, oracle", 0.0,
                         tile == 2.0 ? truth_2deg : trueGrid(camera, tile), {}, {}});
    }
    const double disoccluded = evaluateEyeErrors(scene, camera, proxies, rays, true);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    const std::string scene_name = near_m > 0 ? "near objects at " + formatNumber(near_m) + " m" : "room alone (front wall 3 m)";
    out << "\n" << scene_name << ": disoccluded while moving " << formatNumber(100.0 * disoccluded)
        << " % of eye rays; stereo: " << stereo.matched << " of " << stereo.seen << " tiles matched, inverse depth error p50 "
        << formatNumber(quantile(stereo.inverse_depth_error, 0.5)) << " / p90 "
        << formatNumber(quantile(stereo.inverse_depth_error, 0.9)) << " 1/m, both sweeps " << formatNumber(stereo.ms)
        << " ms CPU (median of " << kTimedRuns << " runs; " << formatNumber(seconds) << " s in all)\n";
    Table table({"proxy", "radius m", "rest p50 deg", "rest p90", "moving p50", "moving p90", "fovea moving p50",
                 "fovea moving p90"});
    nlohmann::json proxies_json = nlohmann::json::array();
    for (const Proxy& proxy : proxies) {
      table.addRow({proxy.label, proxy.grid ? "-" : formatNumber(proxy.radius_m), formatNumber(quantile(proxy.rest.whole, 0.5)),
                    formatNumber(quantile(proxy.rest.whole, 0.9)), formatNumber(quantile(proxy.moving.whole, 0.5)),
                    formatNumber(quantile(proxy.moving.whole, 0.9)), formatNumber(quantile(proxy.moving.fovea, 0.5)),
                    formatNumber(quantile(proxy.moving.fovea, 0.9))});
      nlohmann::json p = {{"proxy", proxy.name}, {"rest", stats(proxy.rest)}, {"moving", stats(proxy.moving)}};
      if (!proxy.grid) p["radius_m"] = proxy.radius_m;
      if (proxy.grid) p["tile_deg"] = proxy.grid->tileDeg();
      proxies_json.push_back(p);
      if (proxy.name == "fixed" || proxy.name == "radius" || proxy.name == "grid" || proxy.name == "radius_oracle" ||
          proxy.name == "grid_oracle") {
        for (const auto& [state, set] : {std::pair{"moving", &proxy.moving}, std::pair{"rest", &proxy.rest}}) {
          keepWorst(std::string("eye_error_") + state + "_p50_deg_" + proxy.name, quantile(set->whole, 0.5));
          keepWorst(std::string("eye_error_") + state + "_p90_deg_" + proxy.name, quantile(set->whole, 0.9));
          keepWorst(std::string("eye_error_") + state + "_fovea_p50_deg_" + proxy.name, quantile(set->fovea, 0.5));
          keepWorst(std::string("eye_error_") + state + "_fovea_p90_deg_" + proxy.name, quantile(set->fovea, 0.9));
        }
      }
    }
    table.print(out);
    keepWorst("disoccluded_fraction", disoccluded);
    keepWorst("depth_ms_per_pair", stereo.ms);
    keepWorst("inverse_depth_error_p50_per_m", quantile(stereo.inverse_depth_error, 0.5));
    keepWorst("inverse_depth_error_p90_per_m", quantile(stereo.inverse_depth_error, 0.9));
    scenes.push_back({{"scene", scene_name},
                      {"near_depth_m", near_m},
                      {"disoccluded_fraction", disoccluded},
                      {"depth_ms_per_pair", stereo.ms},
                      {"tiles_matched", stereo.matched},
                      {"tiles_seen", stereo.seen},
                      {"inverse_depth_error_p50_per_m", quantile(stereo.inverse_depth_error, 0.5)},
                      {"inverse_depth_error_p90_per_m", quantile(stereo.inverse_depth_error, 0.9)},
                      {"proxies", proxies_json}});
  }

  // The sweep's speed against its accuracy: fewer samples and hypotheses, other tiles; the worst
  // scene of each column, moving.
  struct Setting {
    std::string name;
    xr::depth::SphereSweepOptions options;
  };
  std::vector<Setting> settings = {{"5x5 samples, 48 depths, 4 deg (default)", sweep_options}};
  {
    // The same sweep summing one sample at a time (the reference the AVX2 sums are checked against).
    xr::depth::SphereSweepOptions scalar = sweep_options;
    scalar.simd = false;
    settings.push_back({"as default, one sample at a time (no AVX2)", scalar});
  }
  const auto variant = [&](const std::string& name, int side, int hypotheses, double tile) {
    xr::depth::SphereSweepOptions o = sweep_options;
    o.samples_per_side = side;
    o.hypotheses = hypotheses;
    o.tile_deg = tile;
    settings.push_back({name, o});
  };
  variant("4x4 samples, 32 depths, 4 deg", 4, 32, 4.0);
  variant("3x3 samples, 24 depths, 4 deg", 3, 24, 4.0);
  variant("4x4 samples, 32 depths, 6 deg", 4, 32, 6.0);
  variant("5x5 samples, 48 depths, 3 deg", 5, 48, 3.0);
  Table knob({"sweep", "ms/pair (CPU, median of " + std::to_string(kTimedRuns) + " runs)", "tables MB", "grid moving p50 deg", "grid moving p90", "radius fovea moving p50",
              "inverse depth err p90 1/m"});
  nlohmann::json knob_json = nlohmann::json::array();
  for (const Setting& setting : settings) {
    StereoSweeps s = makeSweeps(setting.name, rig, depth_width, depth_height, setting.options);
    double ms = 0, grid_p50 = 0, grid_p90 = 0, radius_fovea = 0, rho_p90 = 0;
    for (std::size_t i = 0; i < built.size(); ++i) {
      const SceneView camera = built[i].view(0, Eigen::Isometry3d::Identity());
      const StereoDepth depth = sweepPair(s, pairs[i], depth_width, depth_height, camera, rig.cameras[0], {}, kTimedRuns);
      std::vector<Proxy> proxies = stereoProxies(depth);
      evaluateEyeErrors(built[i], camera, proxies, ctx.quick ? 21 : 61, false);
      ms = std::max(ms, depth.ms);
      radius_fovea = std::max(radius_fovea, quantile(proxies[0].moving.fovea, 0.5));
      grid_p50 = std::max(grid_p50, quantile(proxies[1].moving.whole, 0.5));
      grid_p90 = std::max(grid_p90, quantile(proxies[1].moving.whole, 0.9));
      rho_p90 = std::max(rho_p90, quantile(depth.inverse_depth_error, 0.9));
    }
    knob.addRow({setting.name, formatNumber(ms), formatNumber(s.left.tableBytes() / 1e6), formatNumber(grid_p50),
                 formatNumber(grid_p90), formatNumber(radius_fovea), formatNumber(rho_p90)});
    knob_json.push_back({{"sweep", setting.name},
                         {"samples_per_side", setting.options.samples_per_side},
                         {"hypotheses", setting.options.hypotheses},
                         {"tile_deg", setting.options.tile_deg},
                         {"simd", setting.options.simd && xr::depth::patchSumsSimdAvailable()},
                         {"depth_ms_per_pair", ms},
                         {"eye_error_moving_p50_deg_grid", grid_p50},
                         {"eye_error_moving_p90_deg_grid", grid_p90},
                         {"eye_error_moving_fovea_p50_deg_radius", radius_fovea},
                         {"inverse_depth_error_p90_per_m", rho_p90}});
  }
  out << "\nThe sweep's speed against its accuracy (worst scene of each column; eye errors moving, "
      << (ctx.quick ? 21 : 61) << "x" << (ctx.quick ? 21 : 61) << " rays):\n";
  knob.print(out);
  // The first two rows differ only in how the sums are taken: eight samples a step must not be
  // slower than one at a time (it was 3.5x slower on one CPU, xr/depth/patch_sums.cpp).
  const double simd_ms = knob_json[0]["depth_ms_per_pair"].get<double>(), scalar_ms = knob_json[1]["depth_ms_per_pair"].get<double>();
  if (knob_json[0]["simd"].get<bool>() && simd_ms > scalar_ms)
    out << "warning: on this CPU the AVX2 sums (" << formatNumber(simd_ms) << " ms a pair) are slower than one sample at a time ("
        << formatNumber(scalar_ms) << " ms)\n";

  worst["gpu_sweep"] = runGpuSweep(ctx, rig, depth_width, depth_height, built, pairs);
  worst["edge_settings"] = runEdgeKnob(ctx, built, stereo_grids, rays);  // the rays of the tables above
  worst["march_settings"] = runMarchKnob(ctx, built, stereo_grids, rays);
  worst["harder_inputs"] = runHarderInputs(ctx, sweeps, rig.cameras[0], depth_width, depth_height);
  worst["motion_baselines"] = runMotionBaselines(ctx, sweeps, rig, depth_width, depth_height);
  worst["depth_ms_per_pair_with_two_motion_views"] = 0.0;  // the worst scene's, the operator app's default
  for (const nlohmann::json& row : worst["motion_baselines"])
    if (row["earlier_rig_positions_m"].size() == 2) keepWorst("depth_ms_per_pair_with_two_motion_views", row["depth_ms_per_pair"].get<double>());
  const ApproachFrames approach = sweepApproach(ctx, sweeps, rig, depth_width, depth_height);
  worst["approaching_object"] = runApproach(ctx, approach);
  worst["filter_settings"] = runFilterKnob(ctx, sweeps, rig, approach, depth_width, depth_height);

  const auto w = [&](const char* key) { return formatNumber(worst[key].get<double>()); };
  out << "\nworst over the scenes (the goals hold for every scene), stereo (oracle): radius fovea moving p50 "
      << w("eye_error_moving_fovea_p50_deg_radius") << " (" << w("eye_error_moving_fovea_p50_deg_radius_oracle")
      << ") deg, goal <= 0.15; grid moving p50 " << w("eye_error_moving_p50_deg_grid") << " ("
      << w("eye_error_moving_p50_deg_grid_oracle") << ") / p90 " << w("eye_error_moving_p90_deg_grid") << " ("
      << w("eye_error_moving_p90_deg_grid_oracle") << ") deg, goal <= 0.1 / 0.5; depth " << w("depth_ms_per_pair")
      << " ms a pair (both cameras, one core; the pair alone), goal <= 10; with two earlier views from the arm's motion "
      << w("depth_ms_per_pair_with_two_motion_views") << " ms\n"
      << "the renderer's cost with the grid: telesphere-bench render; the operator app runs the sweep with "
         "telesphere-xr --depth-proxy radius|grid; end to end with the image latency: telesphere-bench experiments\n";
  worst["depth_resolution"] = {depth_width, depth_height};
  worst["eye_offset_rest_m"] = kRestOffsetM;
  worst["eye_offset_moving_m"] = kMovingOffsetM;
  worst["sweep_settings"] = knob_json;
  worst["scenes"] = scenes;
  return worst;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(depth, telesphere::bench::BenchTopic{
                                  "depth",
                                  "eye-image error of the depth proxies (fixed sphere, one radius, inverse-depth grid) at rest and moving",
                                  [](CLI::App& sub) {
                                    sub.add_option("--scene-depth-m", telesphere::bench::sceneDepthOption(),
                                                   "place the near objects at this depth only (m; default: 0.3 to 10)")
                                        ->check(CLI::Range(0.2, 100.0));
                                  },
                                  telesphere::bench::runDepth});
