// SPDX-License-Identifier: MIT
/// @brief telesphere-truth-check: the ground-truth check of a simulated run (issue: end-to-end
///        truth). Reads the robot's truth (telesphere-robot --truth-out) and the operator app's
///        projection maps (telesphere-xr offscreen --truth-out), evaluates every recorded frame
///        (app/bench/truth/eye_image_truth.h) and prints a table; with --max-p99-deg it fails (exit 1)
///        when the eye-image error's p99 over all pixels and frames is larger, or when fewer than
///        --min-frames frames could be evaluated. Used by the robot+XR loop test and the
///        experiments benchmark. Exit codes: 0 ok, 1 the check failed, 2 bad input.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "calib/calibration_file.h"
#include "app/bench/truth/eye_image_truth.h"

int main(int argc, char** argv) {
  using namespace telesphere;
  CLI::App app{"telesphere-truth-check: what the operator saw against the simulation's truth"};
  std::string robot_truth, xr_truth, calib_path;
  double max_p99_deg = -1.0;
  int min_frames = 1;
  int stride = 2;
  bool quiet = false;
  app.add_option("--robot-truth", robot_truth, "telesphere-robot --truth-out file")->required();
  app.add_option("--xr-truth", xr_truth, "telesphere-xr offscreen --truth-out folder")->required();
  app.add_option("--calib", calib_path, "the TRUE calibration of the synthetic cameras")->required();
  app.add_option("--max-p99-deg", max_p99_deg, "fail when the p99 error is larger (deg; < 0: no limit)");
  app.add_option("--min-frames", min_frames, "fail when fewer frames could be evaluated")->capture_default_str();
  app.add_option("--stride", stride, "evaluate every N-th eye pixel in both directions")->capture_default_str();
  app.add_flag("--quiet", quiet, "only the summary line");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  const auto robot_rows = truth::loadRobotTruth(robot_truth, &error);
  if (!robot_rows) return std::cerr << error << '\n', 2;
  const auto frames = truth::loadXrTruthFrames(xr_truth, &error);
  if (!frames) return std::cerr << error << '\n', 2;
  const auto calibration = calib::loadCalibrationFile(calib_path);
  if (!calibration) return std::cerr << calibration.error().describe() << '\n', 2;
  const robot::cameras::SyntheticScene scene = robot::cameras::defaultScene();

  std::vector<double> all;
  int evaluated_frames = 0, skipped = 0;
  if (!quiet)
    std::printf("| frame | sequence | Δs mm | stamp err mm | stamp err deg | blind %% | error deg p50 | p99 | max |\n"
                "|------:|---------:|------:|-------------:|--------------:|--------:|--------------:|----:|----:|\n");
  for (const auto& frame : *frames) {
    const auto row = robot_rows->find(frame.stereo_sequence);
    if (row == robot_rows->end() || frame.mode != "full6d") {
      ++skipped;
      continue;
    }
    const auto map = truth::loadProjectionMap(xr_truth, frame, &error);
    if (!map) return std::cerr << error << '\n', 2;
    const auto result = truth::evaluateEyeImages(frame, *map, row->second, *calibration, scene, {stride}, &error);
    if (!result) {
      ++skipped;
      if (!quiet) std::printf("| %llu | skipped: %s |\n", static_cast<unsigned long long>(frame.index), error.c_str());
      continue;
    }
    ++evaluated_frames;
    all.insert(all.end(), result->error_deg.begin(), result->error_deg.end());
    if (!quiet)
      std::printf("| %llu | %llu | %.1f | %.3f | %.4f | %.1f | %.4f | %.4f | %.4f |\n",
                  static_cast<unsigned long long>(frame.index), static_cast<unsigned long long>(frame.stereo_sequence),
                  result->eye_camera_distance_m * 1e3, result->stamp_position_error_m * 1e3,
                  result->stamp_angle_error_deg,
                  result->evaluated ? 100.0 * double(result->blind) / double(result->evaluated) : 0.0,
                  truth::quantile(result->error_deg, 0.5), truth::quantile(result->error_deg, 0.99),
                  truth::quantile(result->error_deg, 1.0));
  }
  const double p50 = truth::quantile(all, 0.5), p99 = truth::quantile(all, 0.99);
  std::printf("eye-image error over %d frames (%d skipped), %zu pixels: p50 %.4f deg, p99 %.4f deg, max %.4f deg\n",
              evaluated_frames, skipped, all.size(), p50, p99, truth::quantile(all, 1.0));
  if (evaluated_frames < min_frames) {
    std::printf("FAIL: %d frames evaluated, at least %d needed\n", evaluated_frames, min_frames);
    return 1;
  }
  if (max_p99_deg >= 0 && !(p99 <= max_p99_deg)) {
    std::printf("FAIL: p99 %.4f deg > %.4f deg\n", p99, max_p99_deg);
    return 1;
  }
  return 0;
}
