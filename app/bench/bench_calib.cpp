// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench calib`: calibration accuracy and cost against ground truth
///        (DESIGN.md §6): intrinsic error vs truth and reprojection RMS vs number of views for
///        the 195° double-sphere lens at 4K and 1280×1024 (σ = 0.3 px corner noise), the whole
///        pipeline on rendered images (render → detect → calibrate), hand-eye accuracy vs number
///        of samples, model selection (the candidate models fitted on the same data), and the
///        hand-eye marker's corners by refinement (OpenCV's cornerSubPix against the sides' edges).
#include <chrono>
#include <cmath>
#include <random>

#include "calib/intrinsic_calibration.h"
#include "calib/target_render.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "calib/synthetic/calibration_sessions.h"
#include "calib/synthetic/marker_views.h"

namespace telesphere::bench {
namespace {

constexpr double kNoisePx = 0.3;

struct IntrinsicFigures {
  double rms_px = 0, focal_rel = 0, cx_px = 0, cy_px = 0, xi = 0, alpha = 0, seconds = 0;
  double correlation = NAN;  ///< focal vs distortion multiple correlation
  bool degenerate = false;   ///< the solve warned that the views do not separate the parameters
  int corners = 0;
  bool ok = false;
};

/// `degenerate`: all views fronto-parallel at the image centre instead of spread over the image.
IntrinsicFigures runIntrinsics(const calib::synthetic::SyntheticCamera& cam, int views, std::uint32_t seed,
                               const std::string& model = "ds", bool degenerate = false) {
  std::mt19937 rng(seed);
  const auto grid = calib::synthetic::testGrid();
  const auto poses = degenerate ? calib::synthetic::frontoParallelCentreBoardPoses(grid, views, rng)
                                : calib::synthetic::spreadBoardPoses(cam, grid, views, 100.0 * M_PI / 180, rng);
  calib::CameraViews input;
  input.model = model;
  input.width = cam.width;
  input.height = cam.height;
  for (const auto& T : poses) input.views.push_back(calib::synthetic::observeBoard(cam, grid, T, kNoisePx, rng));
  const auto t0 = std::chrono::steady_clock::now();
  const auto result = calib::calibrateIntrinsics(grid, {input});
  IntrinsicFigures f;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!result) return f;
  f.ok = true;
  const Eigen::VectorXd p = result->cameras[0].calibration.camera.params();
  const Eigen::VectorXd t = cam.camera.params();
  f.rms_px = result->cameras[0].rms_px;
  f.corners = result->cameras[0].corners;
  f.correlation = result->cameras[0].focal_distortion_correlation;
  f.degenerate = result->degenerate();
  if (model == "ds") {
    f.focal_rel = std::max(std::abs(p[0] / t[0] - 1), std::abs(p[1] / t[1] - 1));
    f.cx_px = std::abs(p[2] - t[2]);
    f.cy_px = std::abs(p[3] - t[3]);
    f.xi = std::abs(p[4] - t[4]);
    f.alpha = std::abs(p[5] - t[5]);
  }
  return f;
}

struct HandEyeFigures {
  double mm = 0, deg = 0, seconds = 0;
  bool ok = false;
};

HandEyeFigures runHandEye(const calib::synthetic::SyntheticCamera& cam_l, const calib::synthetic::SyntheticCamera& cam_r,
                          int samples_n, std::uint32_t seed) {
  const auto truth = calib::synthetic::handEyeTruth();
  const auto samples = calib::synthetic::simulateHandEyeSession(truth, cam_l, cam_r, calib::synthetic::trueTCamLCamR(), 0.1,
                                                    samples_n, kNoisePx, seed);
  calib::SystemCalibration system;
  system.cameras.push_back({"cam_l", cam_l.camera, cam_l.width, cam_l.height});
  system.cameras.push_back({"cam_r", cam_r.camera, cam_r.width, cam_r.height});
  system.T_cam_l_cam_r = calib::synthetic::trueTCamLCamR();
  const auto t0 = std::chrono::steady_clock::now();
  const auto result = calib::calibrateHandEye(system, 0.1, samples);
  HandEyeFigures f;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!result) return f;
  f.ok = true;
  const std::pair<Eigen::Isometry3d, Eigen::Isometry3d> pairs[] = {
      {result->T_flange_cam_l, truth.T_flange_cam_l},
      {result->T_robot_mount, truth.T_robot_mount},
      {result->T_wrist_marker, truth.T_wrist_marker}};
  for (const auto& [a, b] : pairs) {
    f.mm = std::max(f.mm, 1e3 * calib::synthetic::translationError(a, b));
    f.deg = std::max(f.deg, calib::synthetic::rotationErrorDeg(a, b));
  }
  return f;
}

/// A right camera for the 4K lens, like lens1280(true) relative to lens1280().
calib::synthetic::SyntheticCamera lens4kRight() {
  Eigen::VectorXd p(6);
  p << 936, 935.5, 1925.1, 1075.8, -0.16, 0.6;
  return {*calib::GenericCamera::create("ds", p), 3840, 2160};
}

double projectNs(const calib::GenericCamera& camera) {
  std::vector<Eigen::Vector3d> points;
  for (const auto& d : calib::synthetic::sphereDirectionsForBench()) points.push_back(d);
  double best = 1e300;
  for (int pass = 0; pass < 3; ++pass) {
    std::size_t valid = 0;
    const auto t0 = std::chrono::steady_clock::now();
    camera.visit([&](const auto& model) {
      for (const auto& p : points) {
        typename std::decay_t<decltype(model)>::Vec2 px;
        valid += model.project(p, px);
      }
    });
    const auto t1 = std::chrono::steady_clock::now();
    if (valid == 0) return NAN;
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / double(points.size()));
  }
  return best;
}

nlohmann::json runCalib(const BenchContext& ctx) {
  nlohmann::json json;
  json["noise_px"] = kNoisePx;
  const double expected_rms = kNoisePx * std::sqrt(2.0);

  // 1. Intrinsics vs number of views.
  Table intr({"image", "views", "corners", "RMS px", "RMS / (σ√2)", "focal err rel", "cx err px",
              "cy err px", "xi err", "alpha err", "f/dist corr", "warning", "solve s"});
  const std::vector<int> view_counts = ctx.quick ? std::vector<int>{10, 20} : std::vector<int>{10, 20, 50, 100};
  std::vector<std::pair<std::string, calib::synthetic::SyntheticCamera>> lenses = {{"1280x1024", calib::synthetic::lens1280()}};
  if (!ctx.quick) lenses.push_back({"3840x2160", calib::synthetic::lens4k()});
  IntrinsicFigures headline;
  for (const auto& [name, cam] : lenses) {
    for (int n : view_counts) {
      ctx.out << "intrinsics: " << name << ", " << n << " views...\n";
      const IntrinsicFigures f = runIntrinsics(cam, n, 100 + static_cast<std::uint32_t>(n));
      if (!f.ok) {
        intr.addRow({name, std::to_string(n), "-", "failed", "", "", "", "", "", "", "", "", formatNumber(f.seconds)});
        continue;
      }
      intr.addRow({name, std::to_string(n), std::to_string(f.corners), formatNumber(f.rms_px, 4),
                   formatNumber(f.rms_px / expected_rms, 4), formatNumber(f.focal_rel, 2),
                   formatNumber(f.cx_px, 2), formatNumber(f.cy_px, 2), formatNumber(f.xi, 2),
                   formatNumber(f.alpha, 2), formatNumber(f.correlation, 6), f.degenerate ? "yes" : "no",
                   formatNumber(f.seconds)});
      json["intrinsics"].push_back({{"image", name}, {"views", n}, {"rms_px", f.rms_px},
                                    {"focal_error_rel", f.focal_rel}, {"cx_error_px", f.cx_px},
                                    {"cy_error_px", f.cy_px}, {"xi_error", f.xi},
                                    {"alpha_error", f.alpha}, {"solve_s", f.seconds}});
      if (n == (ctx.quick ? 20 : 50)) headline = f;
    }
  }
  {
    // The degeneracy check: all views fronto-parallel at the centre must raise the warning.
    ctx.out << "intrinsics: 1280x1024, 20 fronto-parallel centre views (degenerate)...\n";
    const IntrinsicFigures f = runIntrinsics(calib::synthetic::lens1280(), 20, 900, "ds", true);
    intr.addRow({"1280x1024 fronto-parallel centre", "20", f.ok ? std::to_string(f.corners) : "-",
                 f.ok ? formatNumber(f.rms_px, 4) : "failed", f.ok ? formatNumber(f.rms_px / expected_rms, 4) : "",
                 formatNumber(f.focal_rel, 2), formatNumber(f.cx_px, 2), formatNumber(f.cy_px, 2),
                 formatNumber(f.xi, 2), formatNumber(f.alpha, 2), formatNumber(f.correlation, 6),
                 f.degenerate ? "yes" : "no", formatNumber(f.seconds)});
    json["degenerate_set_warned"] = f.degenerate;
    json["degenerate_set_correlation"] = f.correlation;
  }
  json["intrinsics_rms_px"] = headline.rms_px;
  json["focal_error_rel"] = headline.focal_rel;
  json["intrinsics_solve_s"] = headline.seconds;

  // 2. Rendered images → detection → calibration.
  Table pipeline({"image", "views", "views detected", "corners detected", "detect s", "RMS px", "focal err rel",
                  "cx err px", "xi err", "alpha err", "f/dist corr", "warning", "solve s"});
  {
    const auto cam = calib::synthetic::lens1280();
    const auto grid = calib::synthetic::testGrid();
    const int n = ctx.quick ? 12 : 24;
    ctx.out << "pipeline: rendering and detecting " << n << " 1280x1024 views...\n";
    std::mt19937 rng(77);
    const auto poses = calib::synthetic::spreadBoardPoses(cam, grid, n, 100.0 * M_PI / 180, rng);
    calib::CameraViews input;
    input.width = cam.width;
    input.height = cam.height;
    double detect_s = 0;
    int detected = 0, views_detected = 0;
    for (std::size_t v = 0; v < poses.size(); ++v) {
      calib::RenderOptions ro;
      ro.noise_sigma = 2.0;
      ro.noise_seed = static_cast<std::uint32_t>(v + 1);
      const auto image = calib::renderTarget(cam.camera, cam.width, cam.height, poses[v],
                                             calib::aprilGridTexture(grid), ro);
      const auto t0 = std::chrono::steady_clock::now();
      input.views.push_back(calib::detectAprilGrid(image, grid));
      detect_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      detected += static_cast<int>(input.views.back().corner_ids.size());
      views_detected += input.views.back().empty() ? 0 : 1;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const auto result = calib::calibrateIntrinsics(grid, {input});
    const double solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (result) {
      const Eigen::VectorXd p = result->cameras[0].calibration.camera.params(), t = cam.camera.params();
      const double focal = std::max(std::abs(p[0] / t[0] - 1), std::abs(p[1] / t[1] - 1));
      pipeline.addRow({"1280x1024", std::to_string(n), std::to_string(views_detected), std::to_string(detected),
                       formatNumber(detect_s), formatNumber(result->cameras[0].rms_px, 4), formatNumber(focal, 2),
                       formatNumber(std::abs(p[2] - t[2]), 2), formatNumber(std::abs(p[4] - t[4]), 2),
                       formatNumber(std::abs(p[5] - t[5]), 2),
                       formatNumber(result->cameras[0].focal_distortion_correlation, 6),
                       result->degenerate() ? "yes" : "no", formatNumber(solve_s)});
      json["pipeline_rms_px"] = result->cameras[0].rms_px;
      json["pipeline_focal_error_rel"] = focal;
      json["pipeline_degenerate"] = result->degenerate();
    } else {
      pipeline.addRow({"1280x1024", std::to_string(n), std::to_string(views_detected), std::to_string(detected),
                       formatNumber(detect_s), "failed: " + result.failure().message, "", "", "", "", "", "",
                       formatNumber(solve_s)});
    }
  }

  // 3. Hand-eye vs number of samples.
  Table handeye({"image", "samples", "max translation err mm", "max rotation err deg", "solve s"});
  const std::vector<int> sample_counts = ctx.quick ? std::vector<int>{20, 50} : std::vector<int>{10, 20, 50, 100};
  std::vector<std::tuple<std::string, calib::synthetic::SyntheticCamera, calib::synthetic::SyntheticCamera>> pairs = {
      {"1280x1024", calib::synthetic::lens1280(false), calib::synthetic::lens1280(true)}};
  if (!ctx.quick) pairs.push_back({"3840x2160", calib::synthetic::lens4k(), lens4kRight()});
  for (const auto& [name, cam_l, cam_r] : pairs) {
    for (int n : sample_counts) {
      ctx.out << "hand-eye: " << name << ", " << n << " samples...\n";
      const HandEyeFigures f = runHandEye(cam_l, cam_r, n, 500 + static_cast<std::uint32_t>(n));
      handeye.addRow({name, std::to_string(n), f.ok ? formatNumber(f.mm) : "failed",
                      f.ok ? formatNumber(f.deg) : "", formatNumber(f.seconds)});
      json["handeye"].push_back({{"image", name}, {"samples", n}, {"error_mm", f.mm}, {"error_deg", f.deg}});
      if (n == 50 && (ctx.quick || name == "3840x2160")) {
        json["handeye_error_mm"] = f.mm;
        json["handeye_error_deg"] = f.deg;
      }
    }
  }

  // 4. Model selection on the same data.
  Table models({"model", "parameters", "RMS px", "mean px", "project ns", "solve s"});
  {
    const auto cam = calib::synthetic::lens1280();
    std::mt19937 rng(31);
    const auto grid = calib::synthetic::testGrid();
    const auto poses = calib::synthetic::spreadBoardPoses(cam, grid, 20, 100.0 * M_PI / 180, rng);
    calib::CameraViews input;
    input.width = cam.width;
    input.height = cam.height;
    for (const auto& T : poses) input.views.push_back(calib::synthetic::observeBoard(cam, grid, T, kNoisePx, rng));
    for (const std::string model : {"ds", "eucm", "kb4", "pinhole"}) {
      ctx.out << "model selection: " << model << "...\n";
      input.model = model;
      calib::IntrinsicOptions options;
      options.covariance = false;
      options.max_rms_px = 1e9;  // report a poor fit instead of refusing it
      const auto t0 = std::chrono::steady_clock::now();
      const auto result = calib::calibrateIntrinsics(grid, {input}, options);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!result) {
        models.addRow({model, "", "failed", "", "", formatNumber(s)});
        continue;
      }
      const auto& c = result->cameras[0];
      models.addRow({model, std::to_string(c.calibration.camera.params().size()), formatNumber(c.rms_px, 4),
                     formatNumber(c.mean_px, 4), formatNumber(projectNs(c.calibration.camera)),
                     formatNumber(s)});
      json["models"][model] = {{"rms_px", c.rms_px}, {"corners", c.corners}};
    }
  }

  // 5. The hand-eye marker's corners: cornerSubPix against the edge refinement (marker_edge_corners.h).
  Table marker({"off axis", "refinement", "markers", "mean outward px", "RMS px", "detect ms"});
  {
    const auto cam = calib::synthetic::lens1280();
    std::mt19937 rng(5);
    struct Band {
      const char* name;
      double from_deg, to_deg;
      int n;
    };
    const std::vector<Band> bands = {{"0-40 deg", 0, 40, ctx.quick ? 12 : 40},
                                     {"55-80 deg", 55, 80, ctx.quick ? 4 : 12},
                                     {"80-88 deg", 80, 88, ctx.quick ? 4 : 12}};
    for (const Band& band : bands) {
      ctx.out << "marker corners: " << band.n << " markers " << band.name << " off axis...\n";
      const auto poses = calib::synthetic::randomMarkerPosesFacing(band.n, band.from_deg, band.to_deg, rng);
      const std::vector<calib::MarkerCornerRefinement> refinements = {calib::MarkerCornerRefinement::kCornerSubPix,
                                                                      calib::MarkerCornerRefinement::kEdges};
      const auto errors = calib::synthetic::markerCornerErrors(cam, poses, refinements);
      for (std::size_t r = 0; r < refinements.size(); ++r) {
        const auto& e = errors[r];
        const char* name = refinements[r] == calib::MarkerCornerRefinement::kEdges ? "edges" : "cornerSubPix";
        marker.addRow({band.name, name, std::to_string(e.markers) + "/" + std::to_string(band.n),
                       formatNumber(e.mean_outward_px, 3), formatNumber(e.rms_px, 3),
                       formatNumber(e.detect_ms_per_image, 3)});
        json["marker_corners"].push_back({{"off_axis", band.name}, {"refinement", name}, {"markers", e.markers},
                                          {"mean_outward_px", e.mean_outward_px}, {"rms_px", e.rms_px},
                                          {"detect_ms", e.detect_ms_per_image}});
        if (band.from_deg == 0) json[std::string("marker_corner_bias_px_") + name] = e.mean_outward_px;
      }
    }
  }

  ctx.out << "\nIntrinsics from synthetic corners (ds lens, ~195 deg, sigma = " << kNoisePx
          << " px per axis; RMS is of the 2-D error, expected sigma*sqrt(2) = "
          << formatNumber(expected_rms) << " px):\n";
  intr.print(ctx.out);
  ctx.out << "\nWhole pipeline on rendered images (3x3 supersampled, intensity noise 2 grey levels):\n";
  pipeline.print(ctx.out);
  ctx.out << "\nHand-eye (10 cm ArUco marker, stereo, sigma = " << kNoisePx
          << " px; worst of T_flange_cam_l, T_robot_mount, T_wrist_marker):\n";
  handeye.print(ctx.out);
  ctx.out << "\nModel selection (same 20 views of the 1280x1024 ds lens; corners a model cannot "
             "project are not counted):\n";
  models.print(ctx.out);
  ctx.out << "\nMarker corners (10 cm ArUco marker at 0.45-0.8 m through the 1280x1024 lens, tilted up to 34 deg, "
             "rendered 3x3 supersampled with 2 grey levels of noise; mean outward < 0: the marker looks smaller, "
             "hence farther):\n";
  marker.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(calib, telesphere::bench::BenchTopic{
                                  "calib",
                                  "calibration: intrinsic, pipeline, hand-eye and model-selection "
                                  "accuracy against synthetic ground truth",
                                  {},
                                  telesphere::bench::runCalib});
