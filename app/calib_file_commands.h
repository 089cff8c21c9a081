// SPDX-License-Identifier: MIT
/// @brief The calibration-file tools of `telesphere-calib`:
///          model project|unproject --calib FILE --camera N   stdin → stdout, one line per line
///          convert --calib FILE --out FILE --format telesphere|kalibr|basalt
///          info --calib FILE                                 models, parameters, fields of view
///        --calib takes our calibration YAML, a kalibr camchain.yaml or a Basalt calibration
///        JSON. Exit codes: 0 ok, 1 bad files, 2 no such camera, 3 some stdin lines invalid.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace telesphere::app {

struct CalibrationFileCommandOptions {
  std::string calib;
  int camera = 0;                     ///< model: 0 = cam_l (cam0), 1 = cam_r (cam1)
  std::string out, format = "telesphere";  ///< convert
};

/// The parsed subcommands, so that the run knows which one was given.
struct CalibrationFileCommands {
  CLI::App *model, *project, *unproject, *convert, *info;
  bool parsed() const { return model->parsed() || convert->parsed() || info->parsed(); }
};

CalibrationFileCommands addCalibrationFileCommands(CLI::App& app, CalibrationFileCommandOptions& options);
int runCalibrationFileCommand(const CalibrationFileCommands& commands, const CalibrationFileCommandOptions& options);

}  // namespace telesphere::app
