// SPDX-License-Identifier: MIT
/// @brief The depth bench's approaching object and the temporal filter's knobs.
#include "app/bench/depth_bench_approach.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>

#include "app/bench/bench_table.h"
#include "app/bench/depth_bench_inputs.h"
#include "app/bench/prerendered_frames.h"
#include "xr/depth/box_downscale.h"
#include "xr/depth/inverse_depth_filter.h"

namespace telesphere::bench::depth_bench {

using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;
namespace {

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

}  // namespace

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

}  // namespace telesphere::bench::depth_bench
