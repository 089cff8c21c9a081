// SPDX-License-Identifier: MIT
/// @brief The eye-image error of the depth proxies.
#include "app/bench/depth_eye_errors.h"

#include <algorithm>
#include <cmath>

#include "app/bench/bench_table.h"
#include "app/bench/depth_bench_scenes.h"

namespace telesphere::bench::depth_bench {

using Eigen::Vector3d;
using robot::cameras::SceneHit;
using robot::cameras::SceneView;
using robot::cameras::SyntheticScene;

nlohmann::json stats(const ErrorSet& e) {
  return {{"p50_deg", quantile(e.whole, 0.5)},
          {"p90_deg", quantile(e.whole, 0.9)},
          {"fovea_p50_deg", quantile(e.fovea, 0.5)},
          {"fovea_p90_deg", quantile(e.fovea, 0.9)}};
}

std::vector<Vector3d> offsetDirections() {
  std::vector<Vector3d> directions;
  for (int k = 0; k < 8; ++k) directions.emplace_back(std::cos(k * std::numbers::pi / 4), std::sin(k * std::numbers::pi / 4), 0.0);
  directions.emplace_back(0, 0, 1);
  directions.emplace_back(0, 0, -1);
  return directions;
}

double evaluateEyeErrors(const SyntheticScene& scene, const SceneView& camera, std::vector<Proxy>& proxies, int rays,
                         bool with_rest) {
  std::size_t evaluated_moving = 0, disoccluded_moving = 0;
  std::vector<std::optional<xr::render::GridProxyParams>> params;  // once per proxy: O(tiles)
  for (const Proxy& proxy : proxies)
    if (proxy.grid) {
      params.push_back(xr::render::gridProxyParams(*proxy.grid, proxy.edge_slope_per_m_per_deg, proxy.march_step_tiles));
      params.back()->edge_tile = proxy.edge_tile;
    } else {
      params.push_back(std::nullopt);
    }
  for (const bool moving : {false, true}) {
    if (!moving && !with_rest) continue;
    for (const Vector3d& dir : offsetDirections()) {
      const Vector3d o = (moving ? kMovingOffsetM : kRestOffsetM) * dir;
      for (int iy = 0; iy < rays; ++iy)
        for (int ix = 0; ix < rays; ++ix) {
          const double ax = (-1.0 + 2.0 * ix / (rays - 1)) * kEyeHalfFovDeg * kDeg;
          const double ay = (-1.0 + 2.0 * iy / (rays - 1)) * kEyeHalfFovDeg * kDeg;
          const Vector3d d = Vector3d(std::tan(ax), std::tan(ay), 1.0).normalized();
          int object = -1;
          const std::optional<double> t_true = hitDistance(scene, o, d, &object);
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
          for (std::size_t k = 0; k < proxies.size(); ++k) {
            Proxy& proxy = proxies[k];
            int lookups = 0;
            const std::optional<Vector3d> p = proxy.grid ? xr::render::gridProxyHit(*proxy.grid, *params[k], o, d, &lookups)
                                                         : xr::render::sphereProxyHit(proxy.radius_m, o, d);
            if (proxy.grid && moving) proxy.lookups.push_back(lookups);
            if (!p) continue;
            SceneHit shown;
            if (!camera.intersect(p->normalized(), &shown)) continue;
            const Vector3d S = shown.distance * p->normalized() - o;
            const double err = std::atan2(S.cross(d).norm(), S.dot(d)) / kDeg;
            ErrorSet& set = moving ? proxy.moving : proxy.rest;
            set.whole.push_back(err);
            if (fovea) set.fovea.push_back(err);
            if (object > 0) set.objects.push_back(err);
          }
        }
    }
  }
  return evaluated_moving ? static_cast<double>(disoccluded_moving) / evaluated_moving : 0.0;
}

}  // namespace telesphere::bench::depth_bench
