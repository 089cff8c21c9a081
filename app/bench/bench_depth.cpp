// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench depth` (#35): what each depth proxy leaves of the operator's eye-image
///        error when the eye is away from the camera (at rest: 5 mm; moving: 6 cm, the experiments'
///        moving p50 at r = 1 m), on synthetic rooms with near objects at `--scene-depth-m`. Each
///        eye ray shows the scene point the camera sees through the proxy's point on that ray;
///        the error is the angle between the eye ray and the direction from the eye to that
///        point. Eye pixels whose true point the camera cannot see (disoccluded) are counted apart.
///        The proxies take their depth from the scene's truth (an oracle): the table says what
///        each representation can reach, before any depth estimate from the stereo pair.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "robot/cameras/synthetic_scene.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::bench {
namespace {

using Eigen::Vector3d;
using robot::cameras::SceneHit;
using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kEyeHalfFovDeg = 45.0;   // a headset eye, square
constexpr double kFoveaDeg = 10.0;        // ± around the eye's forward axis
constexpr double kRestOffsetM = 0.005;
constexpr double kMovingOffsetM = 0.06;
constexpr double kCentreSigmaDeg = 5.0;  // the single radius's centre weighting (and twice it)
constexpr int kGridSteps = 3;

double& sceneDepthOption() {
  static double depth_m = 0;
  return depth_m;
}

/// The camera at the origin of a room's frame, looking along +z (x right, y down): floor 1.2 m
/// below, ceiling 1.6 m above, side walls 2.5 m away, a wall 1 m behind and one ahead at
/// max(3 m, 1.5 × the near objects' depth). With `near_m` > 0: a 20 cm cube straight ahead and one
/// 25° to the left with their faces at near_m, and a table top 35 cm below the camera from 0.2 m
/// to beyond them (the grasping workspace).
SyntheticScene makeScene(double near_m) {
  SyntheticScene scene;
  const double front = std::max(3.0, 1.5 * near_m);
  Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
  T_world_room.translation() = Vector3d(0.0, -0.2, (front - 1.0) / 2.0);
  robot::cameras::SurfaceStyle style;
  scene.addRoom("room", T_world_room, Vector3d(2.5, 1.4, (front + 1.0) / 2.0), style, style, style, style);
  if (near_m > 0) {
    const auto at = [](const Vector3d& p) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = p;
      return robot::cameras::fixedPose(T);
    };
    scene.addBox("ahead", at({0.0, 0.0, near_m + 0.1}), Vector3d(0.1, 0.1, 0.1), style);
    const double a = 25.0 * kDeg;
    scene.addBox("left", at({-(near_m + 0.1) * std::sin(a), 0.0, (near_m + 0.1) * std::cos(a)}), Vector3d(0.1, 0.1, 0.1),
                 style);
    const double table_far = near_m + 0.5;
    scene.addBox("table", at({0.0, 0.35 + 0.02, (0.2 + table_far) / 2.0}), Vector3d(0.6, 0.02, (table_far - 0.2) / 2.0),
                 style);
  }
  return scene;
}

/// Distance along unit `d` from `origin` (room frame, the camera's orientation) to the scene.
std::optional<double> hitDistance(const SyntheticScene& scene, const Vector3d& origin, const Vector3d& d) {
  Eigen::Isometry3d T_world_origin = Eigen::Isometry3d::Identity();
  T_world_origin.translation() = origin;
  SceneHit hit;
  if (!scene.view(0, T_world_origin).intersect(d, &hit)) return std::nullopt;
  return hit.distance;
}

/// The oracle grid: each tile's median inverse depth over 3 × 3 rays inside it.
xr::render::InverseDepthGrid trueGrid(const SceneView& camera, double tile_deg) {
  xr::render::InverseDepthGrid grid(tile_deg);
  for (int row = 0; row < grid.rows(); ++row)
    for (int col = 0; col < grid.cols(); ++col) {
      std::vector<double> inverse;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          SceneHit hit;
          const Vector3d d = grid.direction(row + (i + 0.5) / 3.0, col + (j + 0.5) / 3.0);
          inverse.push_back(camera.intersect(d, &hit) ? 1.0 / hit.distance : 0.0);
        }
      std::nth_element(inverse.begin(), inverse.begin() + 4, inverse.end());
      grid.at(row, col) = static_cast<float>(inverse[4]);
    }
  return grid;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const auto i = static_cast<std::size_t>(pos);
  return i + 1 < v.size() ? v[i] + (pos - i) * (v[i + 1] - v[i]) : v[i];
}

struct ErrorSet {
  std::vector<double> whole, fovea;  // degrees
};

struct Proxy {
  std::string name, label;
  double radius_m = 0;                                  // the sphere proxies
  std::optional<xr::render::InverseDepthGrid> grid;  // the grid proxies
  ErrorSet rest, moving;
};

nlohmann::json stats(const ErrorSet& e) {
  return {{"p50_deg", quantile(e.whole, 0.5)},
          {"p90_deg", quantile(e.whole, 0.9)},
          {"fovea_p50_deg", quantile(e.fovea, 0.5)},
          {"fovea_p90_deg", quantile(e.fovea, 0.9)}};
}

nlohmann::json runDepth(const BenchContext& ctx) {
  std::vector<double> depths = ctx.quick ? std::vector<double>{0.3, 1.5} : std::vector<double>{0.3, 0.5, 0.8, 1.5, 3.0, 10.0};
  if (sceneDepthOption() > 0) depths = {sceneDepthOption()};
  const int rays = ctx.quick ? 41 : 121;  // per side of the eye image
  std::vector<double> scene_depths = {0.0};  // the room alone first
  scene_depths.insert(scene_depths.end(), depths.begin(), depths.end());

  // Offsets of the eye from the camera: 8 directions across the view and 2 along it.
  std::vector<Vector3d> directions;
  for (int k = 0; k < 8; ++k) directions.emplace_back(std::cos(k * std::numbers::pi / 4), std::sin(k * std::numbers::pi / 4), 0.0);
  directions.emplace_back(0, 0, 1);
  directions.emplace_back(0, 0, -1);

  auto& out = ctx.out;
  out << "depth: eye-image error per proxy, oracle depth; eye " << 2 * kEyeHalfFovDeg << " deg square, " << rays << "x"
      << rays << " rays, fovea +-" << kFoveaDeg << " deg; eye offset at rest " << kRestOffsetM * 1e3 << " mm, moving "
      << kMovingOffsetM * 1e3 << " mm (" << directions.size() << " directions)\n";

  nlohmann::json scenes = nlohmann::json::array();
  nlohmann::json worst = nlohmann::json::object();
  const auto keepWorst = [&](const std::string& key, double v) {
    if (!worst.contains(key) || v > worst[key].get<double>()) worst[key] = v;
  };
  for (double near_m : scene_depths) {
    const SyntheticScene scene = makeScene(near_m);
    const SceneView camera = scene.view(0, Eigen::Isometry3d::Identity());
    const auto t0 = std::chrono::steady_clock::now();
    const xr::render::InverseDepthGrid truth_2deg = trueGrid(camera, 2.0);
    std::vector<Proxy> proxies;
    proxies.push_back({"fixed", "fixed sphere r = 1 m", 1.0, std::nullopt, {}, {}});
    for (double sigma_deg : {kCentreSigmaDeg, 2.0 * kCentreSigmaDeg}) {
      const double radius = xr::render::centreWeightedRadius(truth_2deg, {0, 0, 1}, sigma_deg * kDeg);
      proxies.push_back({sigma_deg == kCentreSigmaDeg ? "radius" : "radius_sigma_" + formatNumber(sigma_deg) + "deg",
                         "one radius, centre sigma " + formatNumber(sigma_deg) + " deg", radius, std::nullopt, {}, {}});
    }
    for (double tile : {10.0, 4.0, 2.0}) {
      const std::string t = formatNumber(tile);
      proxies.push_back({tile == 4.0 ? "grid" : "grid_" + t + "deg", "grid " + t + " deg, " + std::to_string(kGridSteps) + " steps",
                         0.0, tile == 2.0 ? truth_2deg : trueGrid(camera, tile), {}, {}});
    }

    std::size_t evaluated_moving = 0, disoccluded_moving = 0;
    for (const bool moving : {false, true})
      for (const Vector3d& dir : directions) {
        const Vector3d o = (moving ? kMovingOffsetM : kRestOffsetM) * dir;
        for (int iy = 0; iy < rays; ++iy)
          for (int ix = 0; ix < rays; ++ix) {
            const double ax = (-1.0 + 2.0 * ix / (rays - 1)) * kEyeHalfFovDeg * kDeg;
            const double ay = (-1.0 + 2.0 * iy / (rays - 1)) * kEyeHalfFovDeg * kDeg;
            const Vector3d d = Vector3d(std::tan(ax), std::tan(ay), 1.0).normalized();
            const std::optional<double> t_true = hitDistance(scene, o, d);
            if (!t_true) continue;
            const Vector3d X = o + *t_true * d;
            SceneHit seen;
            const bool visible = camera.intersect(X.normalized(), &seen) && seen.distance >= X.norm() - 1e-3;
            if (moving) {
              ++evaluated_moving;
              if (!visible) ++disoccluded_moving;
            }
            if (!visible) continue;
            const bool fovea = std::acos(std::clamp(d.z(), -1.0, 1.0)) <= kFoveaDeg * kDeg;
            for (Proxy& proxy : proxies) {
              const std::optional<Vector3d> p = proxy.grid ? xr::render::gridProxyHit(*proxy.grid, o, d, kGridSteps)
                                                           : xr::render::sphereProxyHit(proxy.radius_m, o, d);
              if (!p) continue;
              SceneHit shown;
              if (!camera.intersect(p->normalized(), &shown)) continue;
              const Vector3d S = shown.distance * p->normalized() - o;
              const double err = std::atan2(S.cross(d).norm(), S.dot(d)) / kDeg;
              ErrorSet& set = moving ? proxy.moving : proxy.rest;
              set.whole.push_back(err);
              if (fovea) set.fovea.push_back(err);
            }
          }
      }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    const std::string scene_name = near_m > 0 ? "near objects at " + formatNumber(near_m) + " m" : "room alone (front wall 3 m)";
    const double disoccluded = evaluated_moving ? static_cast<double>(disoccluded_moving) / evaluated_moving : 0.0;
    out << "\n" << scene_name << ": disoccluded while moving " << formatNumber(100.0 * disoccluded) << " % of eye rays ("
        << formatNumber(seconds) << " s)\n";
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
      if (proxy.name == "fixed" || proxy.name == "radius" || proxy.name == "grid") {
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
    scenes.push_back({{"scene", scene_name}, {"near_depth_m", near_m}, {"disoccluded_fraction", disoccluded}, {"proxies", proxies_json}});
  }
  out << "\nworst over the scenes (the goals hold for every scene): radius fovea moving p50 "
      << formatNumber(worst["eye_error_moving_fovea_p50_deg_radius"].get<double>()) << " deg (goal <= 0.15), grid moving p50 "
      << formatNumber(worst["eye_error_moving_p50_deg_grid"].get<double>()) << " / p90 "
      << formatNumber(worst["eye_error_moving_p90_deg_grid"].get<double>()) << " deg (goal <= 0.1 / 0.5)\n"
      << "depth from the stereo pair, its cost, the renderer's cost and the image latency: not measured yet (#35)\n";
  worst["depth_source"] = "oracle (the scene's true depth)";
  worst["eye_offset_rest_m"] = kRestOffsetM;
  worst["eye_offset_moving_m"] = kMovingOffsetM;
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
