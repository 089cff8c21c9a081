// SPDX-License-Identifier: MIT
/// @brief `telesphere-console calibrate intrinsics --auto`: the intrinsic and stereo calibration
///        run headless against the live robot (issue #15; console/calibration/intrinsics_procedure.h),
///        for labs that script their set-up and for tests. It drives the head, takes stills until
///        the done rule holds, solves, writes the file and prints the figures (--json: as JSON on
///        stdout). Exit codes: 0 done and written; 1 bad arguments or files; 2 the done rule
///        cannot be met (the reason is printed; no file is written); 3 the robot never answered.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace telesphere::app {

struct CalibrateCommandOptions {
  bool automatic = false;
  std::string robot = "tcp://127.0.0.1:5760";
  std::string out, format = "telesphere", model = "ds", initial, target, save_stills;
  int min_views = 20, max_views = 60;
  bool json = false;
  bool compare_models = false;
  double tolerance_px = 1.0;
};

/// Adds `calibrate` with its `intrinsics` subcommand to `app`.
CLI::App* addCalibrateCommand(CLI::App& app, CalibrateCommandOptions& options);
int runCalibrateCommand(const CLI::App& calibrate, const CalibrateCommandOptions& options);

}  // namespace telesphere::app
