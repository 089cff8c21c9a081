// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench wizard`: accuracy against sample count through the calibration wizard
///        (issue #15). One automatic run of the console's intrinsic and stereo procedure against
///        `telesphere-robot --sim` whose cameras really have tests/console/data/calibration_truth.yaml,
///        started from calib/data/sim_calibration.yaml; then the first N samples the wizard kept,
///        in the order it kept them, solved again for each N and compared with the truth: the
///        projection error over the image (every 16th pixel's true ray through the estimate),
///        fx in σ, T_cam_l_cam_r, the done rule's verdict and the solve's time.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "console/calibration/calibration_robot.h"
#include "console/calibration/intrinsics_procedure.h"
#include "robot/link/link_client.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/child_process.h"

namespace telesphere::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kPort = 27990;

struct WizardOptions {
  std::string size;  ///< empty: 1920x1080, quick 1280x720
  int max_views = 0;  ///< 0: 32, quick 8
};
WizardOptions g_options;

/// Where the true ray of every 16th pixel lands through `estimate`: p50 and max of the distance
/// to the pixel, px (pixels whose ray the estimate cannot project count as the image's width).
std::pair<double, double> projectionError(const calib::GenericCamera& truth, const calib::GenericCamera& estimate,
                                          int width, int height) {
  std::vector<double> errors;
  for (int v = 8; v < height; v += 16) {
    for (int u = 8; u < width; u += 16) {
      const Eigen::Vector2d px(u, v);
      Eigen::Vector3d ray;
      if (!truth.unproject(px, ray)) continue;
      Eigen::Vector2d est;
      errors.push_back(estimate.project(ray, est) ? (est - px).norm() : double(width));
    }
  }
  if (errors.empty()) return {NAN, NAN};
  std::sort(errors.begin(), errors.end());
  return {errors[errors.size() / 2], errors.back()};
}

nlohmann::json run(const BenchContext& ctx) {
  const std::string size = !g_options.size.empty() ? g_options.size : ctx.quick ? "1280x720" : "1920x1080";
  const int max_views = g_options.max_views > 0 ? g_options.max_views : ctx.quick ? 8 : 32;
  const fs::path bin = fs::read_symlink("/proc/self/exe").parent_path();
  const fs::path dir = fs::temp_directory_path() / ("telesphere-bench-wizard-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string truth_path = TELESPHERE_SOURCE_DIR "/tests/console/data/calibration_truth.yaml";
  const std::string start_path = TELESPHERE_SOURCE_DIR "/calib/data/sim_calibration.yaml";
  nlohmann::json json;
  json["size"] = size;
  auto truth_file = calib::loadCalibrationFile(truth_path);
  auto start_file = calib::loadCalibrationFile(start_path);
  if (!truth_file || !start_file) {
    json["error"] = "cannot read " + truth_path + " or " + start_path;
    ctx.out << json["error"].get<std::string>() << "\n";
    return json;
  }

  ctx.out << "wizard: telesphere-robot --sim --size " << size << " with the true calibration; automatic run up to "
          << max_views << " samples…\n"
          << std::flush;
  ChildProcess robot({(bin / "telesphere-robot").string(), "--insecure", "--sim", "--port", std::to_string(kPort), "--size", size,
                      "--fps", "5", "--still-timeout-ms", "30000", "--sim-truth", truth_path, "--preview-rate", "0",
                      "--stats-period", "0"},
                     (dir / "robot.log").string());
  if (!robot.running()) {
    json["error"] = "cannot start " + (bin / "telesphere-robot").string();
    ctx.out << json["error"].get<std::string>() << "\n";
    return json;
  }
  link::LinkEndpoints endpoints;
  endpoints.base_port = kPort;
  link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
  for (const auto end = Clock::now() + std::chrono::seconds(120); Clock::now() < end && !client.latestRobotState();)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));

  console::calibration::IntrinsicsProcedureOptions o;
  o.initial = *start_file;
  o.max_views = max_views;
  o.rule.min_views = max_views;  // collect up to max_views, the solve of each N judged below
  o.log = [&](const std::string& line) { ctx.out << "  " << line << "\n" << std::flush; };
  console::calibration::CalibrationRobot calibration_robot(client);
  const auto t0 = Clock::now();
  console::calibration::IntrinsicsOutcome full = console::calibration::runIntrinsicsAuto(calibration_robot, o);
  const double run_s = std::chrono::duration<double>(Clock::now() - t0).count();
  robot.stop();
  json["run_s"] = run_s;
  json["stills"] = full.stills;
  if (!full.collector || full.collector->samples().empty()) {
    json["error"] = "the run kept no samples: " + full.error;
    ctx.out << json["error"].get<std::string>() << "\n";
    return json;
  }
  const int kept = int(full.collector->samples().size());
  const int width = full.collector->width(), height = full.collector->height();
  json["samples"] = kept;
  ctx.out << "wizard: " << kept << " samples in " << formatNumber(run_s) << " s (" << full.stills
          << " stills); solving the first N of them…\n";

  std::string error;
  const auto truth_l = calib::atResolution(truth_file->cameras[0], width, height, &error);
  const auto truth_r = calib::atResolution(truth_file->cameras[1], width, height, &error);
  if (!truth_l || !truth_r || !truth_file->T_cam_l_cam_r) {
    json["error"] = "the true calibration at " + std::to_string(width) + "x" + std::to_string(height) + ": " + error;
    ctx.out << json["error"].get<std::string>() << "\n";
    return json;
  }
  const std::array<calib::CameraCalibration, 2> truth{*truth_l, *truth_r};
  const Eigen::Isometry3d T_true = *truth_file->T_cam_l_cam_r;

  console::calibration::IntrinsicsProcedureOptions solve_options = o;
  solve_options.rule.min_views = 20;  // the wizard's own rule for the verdict
  solve_options.log = nullptr;
  Table table({"samples", "done", "RMS px", "proj err p50 px", "proj err max px", "fx err px", "fx err / σ",
               "T_l_r err mm", "T_l_r err °", "solve s"});
  std::vector<int> counts;
  for (int n : {4, 6, 8, 10, 12, 16, 20, 24, 28, 32})
    if (n < kept) counts.push_back(n);
  counts.push_back(kept);
  for (int n : counts) {
    console::calibration::IntrinsicsCollector subset = *full.collector;
    while (int(subset.samples().size()) > n) subset.remove(subset.samples().size() - 1);
    console::calibration::IntrinsicsOutcome out;
    const auto ts = Clock::now();
    console::calibration::solveCollected(std::move(subset), solve_options, out);
    const double solve_s = std::chrono::duration<double>(Clock::now() - ts).count();
    nlohmann::json row{{"samples", n}, {"done", out.done}, {"solve_s", solve_s}};
    if (!out.result) {
      row["error"] = out.error;
      table.addRow({std::to_string(n), "no", "—", "—", "—", "—", "—", "—", "—", formatNumber(solve_s)});
      json["rows"].push_back(row);
      continue;
    }
    double p50 = 0, worst = 0, rms = 0;
    for (int c = 0; c < 2; ++c) {
      const auto [m, w] = projectionError(truth[std::size_t(c)].camera, out.result->cameras[std::size_t(c)].calibration.camera,
                                          width, height);
      p50 = std::max(p50, m);
      worst = std::max(worst, w);
      rms = std::max(rms, out.result->cameras[std::size_t(c)].rms_px);
    }
    const calib::CameraIntrinsicResult& left = out.result->cameras[0];
    const double fx_err = left.calibration.camera.params()[0] - truth[0].camera.params()[0];
    const double fx_sigma = left.param_stddev.empty() ? NAN : left.param_stddev[0];
    double t_mm = NAN, r_deg = NAN;
    if (out.result->T_cam_l_cam_r) {
      const Eigen::Isometry3d d = T_true.inverse() * *out.result->T_cam_l_cam_r;
      t_mm = d.translation().norm() * 1000;
      r_deg = Eigen::AngleAxisd(d.linear()).angle() * 180 / M_PI;
    }
    row.update({{"rms_px", rms}, {"projection_error_px_p50", p50}, {"projection_error_px_max", worst},
                {"fx_error_px", fx_err}, {"fx_error_sigma", fx_err / fx_sigma}, {"T_cam_l_cam_r_error_mm", t_mm},
                {"T_cam_l_cam_r_error_deg", r_deg}, {"degenerate", out.result->degenerate()}});
    table.addRow({std::to_string(n), out.done ? "yes" : "no", formatNumber(rms), formatNumber(p50), formatNumber(worst),
                  formatNumber(fx_err), formatNumber(fx_err / fx_sigma), formatNumber(t_mm), formatNumber(r_deg),
                  formatNumber(solve_s)});
    json["rows"].push_back(row);
  }
  ctx.out << "\nAccuracy against sample count through the wizard (" << size
          << "; errors against the true calibration; both cameras, the worse one; proj err: every 16th "
             "pixel's true ray through the estimate):\n";
  table.print(ctx.out);
  fs::remove_all(dir);
  return json;
}

TELESPHERE_BENCH_TOPIC(wizard, BenchTopic{
    "wizard",
    "calibration wizard: accuracy against sample count on a simulated robot with a known true calibration",
    [](CLI::App& c) {
      c.add_option("--size", g_options.size, "camera image size WxH (default 1920x1080, --quick 1280x720)");
      c.add_option("--max-views", g_options.max_views, "samples the run collects at most (default 32, --quick 8)");
    },
    run});

}  // namespace
}  // namespace telesphere::bench
