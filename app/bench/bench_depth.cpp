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
#include "app/bench/depth_bench_scenes.h"
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

constexpr double kCentreSigmaDeg = 5.0;  // the single radius's centre weighting (and twice it)

double& sceneDepthOption() {
  static double depth_m = 0;
  return depth_m;
}

/// Both cameras' sweeps for one setting (tables built once; the first pair is swept once untimed,
/// so that the tables' first touch is not counted against every frame after it).
struct StereoSweeps {
  std::string name;
  xr::depth::SphereSweep left, right;
  bool warm = false;
};

StereoSweeps makeSweeps(const std::string& name, const calib::SystemCalibration& rig, int width, int height,
                        const xr::depth::SphereSweepOptions& options) {
  return {name,
          xr::depth::SphereSweep(rig.cameras[0].camera, width, height, rig.cameras[1].camera, width, height,
                                 rig.T_cam_l_cam_r->inverse(), options),
          xr::depth::SphereSweep(rig.cameras[1].camera, width, height, rig.cameras[0].camera, width, height,
                                 *rig.T_cam_l_cam_r, options)};
}

/// One pair through both sweeps: the left camera's grid, the CPU time of both, and the grid's
/// inverse-depth error over the tiles the left camera sees against the truth at the same tiles.
struct StereoDepth {
  xr::depth::SweepResult left;
  double ms = 0;
  int matched = 0, seen = 0, decided_by_motion = 0;
  std::vector<double> inverse_depth_error;
};

/// The tiles of `grid` whose centre `camera` sees inside its width × height image.
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

/// `earlier`: per camera (left, right), its views from earlier poses of the rig (SphereSweep::estimate).
StereoDepth sweepPair(StereoSweeps& sweeps, const StereoGrey& pair, int width, int height, const SceneView& camera,
                      const calib::CameraCalibration& left_camera,
                      const std::array<std::vector<xr::depth::EarlierView>, 2>& earlier = {}) {
  const xr::depth::GreyImage left{pair.left.data(), width, height, width};
  const xr::depth::GreyImage right{pair.right.data(), width, height, width};
  if (!sweeps.warm) {
    sweeps.left.estimate(left, right);
    sweeps.right.estimate(right, left);
    sweeps.warm = true;
  }
  StereoDepth out;
  const double cpu0 = threadCpuSeconds();
  out.left = sweeps.left.estimate(left, right, earlier[0]);
  const xr::depth::SweepResult right_result = sweeps.right.estimate(right, left, earlier[1]);
  out.ms = 1e3 * (threadCpuSeconds() - cpu0);
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

/// A sweep's figures with its stereo proxies (stereoProxies order, moving eye errors evaluated):
/// matched tiles, inverse-depth error, the radius and its fovea error, the grid's errors.
nlohmann::json stereoFigures(const StereoDepth& depth, const std::vector<Proxy>& proxies) {
  return {{"tiles_matched_fraction", depth.seen ? static_cast<double>(depth.matched) / depth.seen : 0.0},
          {"inverse_depth_error_p50_per_m", quantile(depth.inverse_depth_error, 0.5)},
          {"inverse_depth_error_p90_per_m", quantile(depth.inverse_depth_error, 0.9)},
          {"radius_m", proxies[0].radius_m},
          {"eye_error_moving_fovea_p50_deg_radius", quantile(proxies[0].moving.fovea, 0.5)},
          {"eye_error_moving_p50_deg_grid", quantile(proxies[1].moving.whole, 0.5)},
          {"eye_error_moving_p90_deg_grid", quantile(proxies[1].moving.whole, 0.9)}};
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

/// What happens to the pair between the sensors and the sweep: the robot's JPEG, sensor noise, a
/// stereo calibration the cameras no longer match. Applied at the capture size, before the
/// operator's box filter down to the sweep's size.
struct InputVariant {
  std::string name;
  int jpeg_quality = 0;      // 0: no JPEG
  double noise_grey = 0;     // σ of Gaussian noise per capture pixel, grey levels
  Vector3d rig_error_deg{0, 0, 0};  // the right camera turned about its x, y, z axes
};

/// The capture-size grey pair as the operator would sweep it: noise, JPEG there and back (the
/// robot's encoder, the XR app's decoder), then box-filtered by `factor`.
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

/// Harder inputs on the 0.5 m scene and the stripes: each variant's matched tiles, inverse-depth
/// error and the stereo proxies' moving eye errors.
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

/// An object approaching the cameras at 0.5 m/s from 1.5 m to 0.3 m, swept at 10 Hz (5 Hz quick):
/// each image's scene and its left camera's sweep (the filters run over these afterwards).
struct ApproachFrames {
  double rate_hz = 10.0, speed_m_s = 0.5, from_m = 1.5, to_m = 0.3;
  std::vector<SyntheticScene> scenes;
  std::vector<xr::depth::SweepResult> sweeps;
};

ApproachFrames sweepApproach(const BenchContext& ctx, StereoSweeps& sweeps, const calib::SystemCalibration& rig, int depth_width,
                             int depth_height) {
  ApproachFrames frames;
  if (ctx.quick) frames.rate_hz = 5.0;
  const int steps = static_cast<int>(std::floor((frames.from_m - frames.to_m) / frames.speed_m_s * frames.rate_hz)) + 1;
  for (int k = 0; k < steps; ++k) {
    const SyntheticScene& scene = frames.scenes.emplace_back(makeApproachScene(frames.from_m - frames.speed_m_s * k / frames.rate_hz));
    const SceneView camera = scene.view(0, Eigen::Isometry3d::Identity());
    frames.sweeps.push_back(sweepPair(sweeps, renderPair(scene, rig, depth_width, depth_height, 2), depth_width, depth_height, camera,
                                      rig.cameras[0])
                                .left);
  }
  return frames;
}

/// Per image, the moving eye error (fovea p50, field p90) of a proxy; then over the images.
struct Series {
  std::string key, name;
  std::vector<double> fovea_p50, whole_p90;
  double foveaMedian() const { return quantile(fovea_p50, 0.5); }
  double foveaWorst() const { return *std::max_element(fovea_p50.begin(), fovea_p50.end()); }
  double wholeMedian() const { return quantile(whole_p90, 0.5); }
  double wholeWorst() const { return *std::max_element(whole_p90.begin(), whole_p90.end()); }
};

/// The approach through a filter (none: the sweeps' own grids): the radius and grid of each image's
/// sweep, and with `late` also those of the sweep before (what the renderer has while this
/// image's sweep runs). Order: radius, grid[, radius_late, grid_late].
std::vector<Series> approachSeries(const ApproachFrames& frames, const std::optional<xr::depth::InverseDepthFilterOptions>& filter_options,
                                   int rays, bool late, int* snapped_images = nullptr) {
  std::vector<Series> series = {{"radius", "radius, this image's sweep", {}, {}}, {"grid", "grid, this image's sweep", {}, {}}};
  if (late) {
    series.push_back({"radius_late", "radius, one sweep late", {}, {}});
    series.push_back({"grid_late", "grid, one sweep late", {}, {}});
  }
  std::optional<xr::depth::InverseDepthFilter> filter;
  if (filter_options) filter.emplace(*filter_options);
  std::optional<xr::render::InverseDepthGrid> previous;
  const double sigma = kCentreSigmaDeg * kDeg;
  for (std::size_t k = 0; k < frames.scenes.size(); ++k) {
    const xr::depth::SweepResult& sweep = frames.sweeps[k];
    const xr::render::InverseDepthGrid grid =
        filter ? filter->update(sweep.inverse_depth, sweep.confidence, static_cast<std::int64_t>(k * 1e9 / frames.rate_hz))
               : sweep.inverse_depth;
    if (snapped_images && filter) *snapped_images += filter->snapped() > 0;
    std::vector<Proxy> proxies;
    proxies.push_back({"radius", "", xr::render::centreWeightedRadius(grid, {0, 0, 1}, sigma), std::nullopt, {}, {}});
    proxies.push_back({"grid", "", 0.0, grid, {}, {}});
    if (late && previous) {
      proxies.push_back({"radius_late", "", xr::render::centreWeightedRadius(*previous, {0, 0, 1}, sigma), std::nullopt, {}, {}});
      proxies.push_back({"grid_late", "", 0.0, *previous, {}, {}});
    }
    const SyntheticScene& scene = frames.scenes[k];
    evaluateEyeErrors(scene, scene.view(0, Eigen::Isometry3d::Identity()), proxies, rays, false);
    for (std::size_t i = 0; i < proxies.size(); ++i) {
      series[i].fovea_p50.push_back(quantile(proxies[i].moving.fovea, 0.5));
      series[i].whole_p90.push_back(quantile(proxies[i].moving.whole, 0.9));
    }
    previous = grid;
  }
  return series;
}

/// The approach with the default filter: the fixed sphere, the radius and grid of each image's
/// sweep and of the sweep before, and the grid unfiltered.
nlohmann::json runApproach(const BenchContext& ctx, const ApproachFrames& frames) {
  const int rays = ctx.quick ? 21 : 41;
  int snapped_images = 0;
  std::vector<Series> filtered = approachSeries(frames, xr::depth::InverseDepthFilterOptions{}, rays, true, &snapped_images);
  Series unfiltered = approachSeries(frames, std::nullopt, rays, false)[1];
  unfiltered.key = "grid_unfiltered";
  unfiltered.name = "grid, unfiltered";
  Series fixed{"fixed", "fixed sphere r = 1 m", {}, {}};
  for (const SyntheticScene& scene : frames.scenes) {
    std::vector<Proxy> proxies = {{"fixed", "", 1.0, std::nullopt, {}, {}}};
    evaluateEyeErrors(scene, scene.view(0, Eigen::Isometry3d::Identity()), proxies, rays, false);
    fixed.fovea_p50.push_back(quantile(proxies[0].moving.fovea, 0.5));
    fixed.whole_p90.push_back(quantile(proxies[0].moving.whole, 0.9));
  }
  const std::vector<Series> series = {fixed, filtered[0], filtered[2], filtered[1], filtered[3], unfiltered};
  auto& out = ctx.out;
  out << "\nAn object approaching at " << frames.speed_m_s << " m/s from " << frames.from_m << " to " << frames.to_m
      << " m, swept at " << frames.rate_hz << " Hz through the temporal filter (" << frames.scenes.size() << " images, "
      << snapped_images << " with tiles that snapped); per image the moving eye error, then over the images:\n";
  Table table({"proxy", "fovea p50: median deg", "worst image", "whole p90: median deg", "worst image"});
  nlohmann::json rows = nlohmann::json::object();
  for (const Series& s : series) {
    table.addRow({s.name, formatNumber(s.foveaMedian()), formatNumber(s.foveaWorst()), formatNumber(s.wholeMedian()),
                  formatNumber(s.wholeWorst())});
    rows[s.key] = {{"proxy", s.name},
                   {"fovea_moving_p50_deg_median", s.foveaMedian()},
                   {"fovea_moving_p50_deg_worst", s.foveaWorst()},
                   {"moving_p90_deg_median", s.wholeMedian()},
                   {"moving_p90_deg_worst", s.wholeWorst()}};
  }
  table.print(out);
  return {{"speed_m_s", frames.speed_m_s}, {"rate_hz", frames.rate_hz}, {"from_m", frames.from_m}, {"to_m", frames.to_m},
          {"images", frames.scenes.size()}, {"images_with_snaps", snapped_images}, {"proxies", rows}};
}

/// The temporal filter's knobs both ways: what the operator sees swim at rest (a still scene, a
/// fresh σ 8 sensor noise on every capture) against how far an approaching object is off.
/// Swim: a change Δρ of the proxy's inverse depth moves what a moving eye (6 cm) sees by
/// 6 cm · Δρ rad; per frame the p90 over the tiles the camera sees (the grid), or the radius's.
nlohmann::json runFilterKnob(const BenchContext& ctx, StereoSweeps& sweeps, const calib::SystemCalibration& rig,
                             const ApproachFrames& approach, int depth_width, int depth_height) {
  const int factor = ctx.quick ? 2 : 4, frames = ctx.quick ? 10 : 30;
  const int capture_width = depth_width * factor, capture_height = depth_height * factor;
  const SyntheticScene scene = makeScene(0.5);
  const SceneView camera = scene.view(0, Eigen::Isometry3d::Identity());
  const StereoGrey capture = renderPair(scene, simulatedRig(capture_width, capture_height), capture_width, capture_height, 1);
  std::vector<xr::depth::SweepResult> still;
  for (int k = 0; k < frames; ++k) {
    const StereoGrey pair = degradeAndShrink(capture, capture_width, capture_height, factor, {"noise", 0, 8.0, {0, 0, 0}},
                                             1000 + static_cast<std::uint32_t>(k));
    still.push_back(sweepPair(sweeps, pair, depth_width, depth_height, camera, rig.cameras[0]).left);
  }
  const std::vector<std::pair<int, int>> seen_tiles = seenTiles(still.front().inverse_depth, rig.cameras[0], depth_width, depth_height);
  struct Setting {
    std::string name;
    std::optional<xr::depth::InverseDepthFilterOptions> options;
  };
  const xr::depth::InverseDepthFilterOptions defaults;
  const auto with = [&](double tau_s, double rate, double snap, const std::string& note = "") {
    xr::depth::InverseDepthFilterOptions o = defaults;
    o.time_constant_s = tau_s;
    o.max_rate_per_m_s = rate;
    o.snap_per_m = snap;
    const bool is_default = o.time_constant_s == defaults.time_constant_s && o.max_rate_per_m_s == defaults.max_rate_per_m_s &&
                            o.snap_per_m == defaults.snap_per_m;
    return Setting{"tau " + formatNumber(tau_s) + " s, " + formatNumber(rate) + " 1/m/s, snap " + formatNumber(snap) + " 1/m" +
                       (is_default ? " (default)" : note),
                   o};
  };
  const std::vector<Setting> settings = {{"none (each sweep as it is)", std::nullopt},
                                         with(0.15, 4.0, 0.5, " (the default before)"),
                                         with(0.15, 8.0, 0.5),
                                         with(defaults.time_constant_s, defaults.max_rate_per_m_s, defaults.snap_per_m),
                                         with(0.05, 4.0, 0.5),
                                         with(0.05, 8.0, 0.25),
                                         with(0.3, 4.0, 0.5)};
  const double swim_scale_deg = kMovingOffsetM / kDeg;  // Δρ (1/m) → degrees for the moving eye
  const int rays = ctx.quick ? 21 : 41;
  Table table({"filter", "swim at rest: grid p90 deg", "radius p90 deg", "approaching: grid fovea p50 median deg", "worst image",
               "radius fovea p50 median", "worst image"});
  nlohmann::json rows = nlohmann::json::array();
  for (const Setting& setting : settings) {
    std::optional<xr::depth::InverseDepthFilter> filter;
    if (setting.options) filter.emplace(*setting.options);
    std::optional<xr::render::InverseDepthGrid> previous;
    double previous_rho = 0;
    std::vector<double> grid_swim, radius_swim;
    for (int k = 0; k < frames; ++k) {
      const xr::render::InverseDepthGrid grid =
          filter ? filter->update(still[k].inverse_depth, still[k].confidence, static_cast<std::int64_t>(k * 1e8)) : still[k].inverse_depth;
      const double rho = 1.0 / xr::render::centreWeightedRadius(grid, {0, 0, 1}, kCentreSigmaDeg * kDeg);
      if (previous) {
        std::vector<double> changes;
        for (const auto& [row, col] : seen_tiles) changes.push_back(std::abs(grid.at(row, col) - previous->at(row, col)));
        grid_swim.push_back(quantile(changes, 0.9) * swim_scale_deg);
        radius_swim.push_back(std::abs(rho - previous_rho) * swim_scale_deg);
      }
      previous = grid;
      previous_rho = rho;
    }
    const std::vector<Series> moving = approachSeries(approach, setting.options, rays, false);
    table.addRow({setting.name, formatNumber(quantile(grid_swim, 0.9)), formatNumber(quantile(radius_swim, 0.9)),
                  formatNumber(moving[1].foveaMedian()), formatNumber(moving[1].foveaWorst()), formatNumber(moving[0].foveaMedian()),
                  formatNumber(moving[0].foveaWorst())});
    nlohmann::json row = {{"filter", setting.name},
                          {"swim_at_rest_p90_deg_grid", quantile(grid_swim, 0.9)},
                          {"swim_at_rest_p90_deg_radius", quantile(radius_swim, 0.9)},
                          {"approaching_fovea_p50_deg_median_grid", moving[1].foveaMedian()},
                          {"approaching_fovea_p50_deg_worst_grid", moving[1].foveaWorst()},
                          {"approaching_fovea_p50_deg_median_radius", moving[0].foveaMedian()},
                          {"approaching_fovea_p50_deg_worst_radius", moving[0].foveaWorst()}};
    if (setting.options)
      row["options"] = {{"time_constant_s", setting.options->time_constant_s},
                        {"max_rate_per_m_s", setting.options->max_rate_per_m_s},
                        {"snap_per_m", setting.options->snap_per_m}};
    rows.push_back(row);
  }
  ctx.out << "\nThe temporal filter both ways: at rest (the 0.5 m scene, " << frames
          << " captures at 10 Hz with fresh sensor noise sigma 8 at " << capture_width << "x" << capture_height
          << ") the frame-to-frame swim a moving eye (6 cm) sees, p90 over frames; approaching, the eye error as above:\n";
  table.print(ctx.out);
  return rows;
}

/// A second baseline from the arm's motion (SphereSweep's earlier views): both cameras' images from
/// where the rig was before (translated, not turned), swept with the pair now. On the stripes, which
/// the pair alone cannot decide, and on the 0.5 m scene, which it can (what the views cost there).
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
  Table table({"scene", "earlier rig positions", "ms/pair (CPU)", "tiles matched %", "decided by the views", "inv depth err p50 1/m",
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
      const StereoDepth depth = sweepPair(sweeps, pair, width, height, camera, rig.cameras[0], earlier);
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
    const StereoDepth stereo = sweepPair(sweeps, pair, depth_width, depth_height, camera, rig.cameras[0]);
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
        << " ms CPU (" << formatNumber(seconds) << " s in all)\n";
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
  Table knob({"sweep", "ms/pair (CPU)", "tables MB", "grid moving p50 deg", "grid moving p90", "radius fovea moving p50",
              "inverse depth err p90 1/m"});
  nlohmann::json knob_json = nlohmann::json::array();
  for (const Setting& setting : settings) {
    StereoSweeps s = makeSweeps(setting.name, rig, depth_width, depth_height, setting.options);
    double ms = 0, grid_p50 = 0, grid_p90 = 0, radius_fovea = 0, rho_p90 = 0;
    for (std::size_t i = 0; i < built.size(); ++i) {
      const SceneView camera = built[i].view(0, Eigen::Isometry3d::Identity());
      const StereoDepth depth = sweepPair(s, pairs[i], depth_width, depth_height, camera, rig.cameras[0]);
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
