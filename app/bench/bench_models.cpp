// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench models`: project and unproject cost per model in float and double
///        (ns per point over a batch of 1 M random valid points; best of 5 passes), next to each
///        model's worst pixel round-trip error over its whole valid image region and the field
///        of view it represents. The table users read to pick the simplest model that is fast
///        and accurate enough.
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "calib/synthetic/typical_lenses.h"

namespace telesphere::bench {
namespace {

using calib::synthetic::TypicalLens;
constexpr int kWidth = calib::synthetic::kTypicalSensorWidthPx;
constexpr int kHeight = calib::synthetic::kTypicalSensorHeightPx;

struct Batch {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
};

/// Random points in front of and beside the camera whose pixels land in the image.
template <typename Camera>
Batch makeBatch(const Camera& cam, std::size_t n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale(0.2, 20.0);
  Batch batch;
  batch.points.reserve(n);
  batch.pixels.reserve(n);
  while (batch.points.size() < n) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    if (p.squaredNorm() > 1.0 || p.squaredNorm() < 1e-6) continue;
    p *= scale(rng) / p.norm();
    Eigen::Vector2d px;
    if (!cam.project(p, px) || px.x() < 0 || px.y() < 0 || px.x() > kWidth - 1 ||
        px.y() > kHeight - 1)
      continue;
    batch.points.push_back(p);
    batch.pixels.push_back(px);
  }
  return batch;
}

/// Best-of-`passes` wall time per call of f over n items, in ns.
template <typename F>
double nsPerItem(std::size_t n, int passes, F&& f) {
  double best = 1e300;
  for (int pass = 0; pass < passes; ++pass) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / double(n));
  }
  return best;
}

struct ModelFigures {
  double project_ns = 0, unproject_ns = 0;
};

template <typename Camera>
ModelFigures timeModel(const Camera& cam, const Batch& batch, int passes) {
  using S = typename Camera::Scalar;
  using Vec2 = typename Camera::Vec2;
  using Vec3 = typename Camera::Vec3;
  const std::size_t n = batch.points.size();
  std::vector<Vec3> points(n);
  std::vector<Vec2> pixels(n), out_px(n);
  std::vector<Vec3> out_d(n);
  for (std::size_t i = 0; i < n; ++i) {
    points[i] = batch.points[i].cast<S>();
    pixels[i] = batch.pixels[i].cast<S>();
  }
  std::size_t valid = 0;
  ModelFigures f;
  f.project_ns = nsPerItem(n, passes, [&] {
    for (std::size_t i = 0; i < n; ++i) valid += cam.project(points[i], out_px[i]);
  });
  f.unproject_ns = nsPerItem(n, passes, [&] {
    for (std::size_t i = 0; i < n; ++i) valid += cam.unproject(pixels[i], out_d[i]);
  });
  if (valid == 0) throw std::runtime_error("no valid point in the batch");
  return f;
}

/// Worst |project(unproject(px)) − px| over every pixel centre (step 2 px) that unprojects.
template <typename Camera>
std::pair<double, double> worstRoundTrip(const Camera& cam, int step) {
  using S = typename Camera::Scalar;
  double worst = 0, max_angle = 0;
  for (int v = 0; v < kHeight; v += step) {
    for (int u = 0; u < kWidth; u += step) {
      const typename Camera::Vec2 px{S(u), S(v)};
      typename Camera::Vec3 d;
      if (!cam.unproject(px, d)) continue;
      typename Camera::Vec2 back;
      if (!cam.project(d, back)) return {INFINITY, 0};
      worst = std::max(worst, static_cast<double>((back - px).norm()));
      max_angle = std::max(max_angle, std::acos(std::clamp(static_cast<double>(d.z()), -1.0, 1.0)));
    }
  }
  return {worst, max_angle};
}

template <template <typename> class Model>
void measure(const BenchContext& ctx, Table& table, nlohmann::json& json) {
  const Model<double> cam(TypicalLens<Model>::parameters());
  const Model<float> cam_f = cam.template cast<float>();
  const std::size_t n = ctx.quick ? 100000 : 1000000;
  const int passes = ctx.quick ? 2 : 5;
  const Batch batch = makeBatch(cam, n);
  const ModelFigures d = timeModel(cam, batch, passes);
  const ModelFigures f = timeModel(cam_f, batch, passes);
  const int step = ctx.quick ? 8 : 2;
  const auto [err_d, seen_d] = worstRoundTrip(cam, step);
  const auto [err_f, seen_f] = worstRoundTrip(cam_f, step);
  const double model_fov_deg = 2 * cam.maxAngle() * 180 / M_PI;
  const double image_fov_deg = 2 * seen_d * 180 / M_PI;
  const std::string name(Model<double>::kName);
  table.addRow({name, formatNumber(d.project_ns), formatNumber(d.unproject_ns),
                formatNumber(f.project_ns), formatNumber(f.unproject_ns), formatNumber(err_d, 2),
                formatNumber(err_f, 2), formatNumber(model_fov_deg, 4),
                formatNumber(image_fov_deg, 4)});
  json[name + "_project_ns"] = d.project_ns;
  json[name + "_unproject_ns"] = d.unproject_ns;
  json["models"][name] = {{"project_ns_double", d.project_ns},
                          {"unproject_ns_double", d.unproject_ns},
                          {"project_ns_float", f.project_ns},
                          {"unproject_ns_float", f.unproject_ns},
                          {"max_roundtrip_error_px_double", err_d},
                          {"max_roundtrip_error_px_float", err_f},
                          {"model_fov_deg", model_fov_deg},
                          {"image_diagonal_fov_deg", image_fov_deg}};
}

nlohmann::json runModels(const BenchContext& ctx) {
  Table table({"model", "project ns (double)", "unproject ns (double)", "project ns (float)",
               "unproject ns (float)", "max round trip px (double)", "max round trip px (float)",
               "model FoV deg", "image FoV deg (diag.)"});
  nlohmann::json json;
  json["points"] = ctx.quick ? 100000 : 1000000;
  json["image"] = {kWidth, kHeight};
  measure<calib::DoubleSphereCamera>(ctx, table, json);
  measure<calib::ExtendedUnifiedCamera>(ctx, table, json);
  measure<calib::KannalaBrandtCamera>(ctx, table, json);
  measure<calib::PinholeRadtanCamera>(ctx, table, json);
  ctx.out << "Camera models on a " << kWidth << "x" << kHeight << " image, "
          << json["points"].get<int>() << " random valid points per batch, best of "
          << (ctx.quick ? 2 : 5) << " passes:\n";
  table.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(models, telesphere::bench::BenchTopic{
                                   "models",
                                   "camera models: project/unproject cost and round-trip accuracy",
                                   {},
                                   telesphere::bench::runModels});
