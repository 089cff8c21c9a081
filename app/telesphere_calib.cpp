// SPDX-License-Identifier: MIT
/// @brief telesphere-calib: calibration and camera-model tools; each command is a file of its own:
///   model project|unproject, convert, info       app/calib_file_commands.h
///   intrinsics, report                           app/calib_intrinsics_command.h
///   handeye                                      app/calib_handeye_command.h
/// --calib takes our calibration YAML, a kalibr camchain.yaml or a Basalt calibration JSON.
#include <CLI/CLI.hpp>

#include "app/calib_file_commands.h"
#include "app/calib_handeye_command.h"
#include "app/calib_intrinsics_command.h"

int main(int argc, char** argv) {
  using namespace telesphere::app;
  CLI::App app{"telesphere-calib: calibration and camera-model tools"};
  app.require_subcommand(1);
  CalibrationFileCommandOptions file_options;
  const CalibrationFileCommands file_commands = addCalibrationFileCommands(app, file_options);
  IntrinsicsCommandOptions intrinsics_options;
  CLI::App* intrinsics = addIntrinsicsCommand(app, intrinsics_options);
  HandEyeCommandOptions handeye_options;
  CLI::App* handeye = addHandEyeCommand(app, handeye_options);
  ReportCommandOptions report_options;
  CLI::App* report = addReportCommand(app, report_options);
  CLI11_PARSE(app, argc, argv);
  if (intrinsics->parsed()) return runIntrinsicsCommand(intrinsics_options);
  if (handeye->parsed()) return runHandEyeCommand(handeye_options);
  if (report->parsed()) return runReportCommand(report_options);
  return runCalibrationFileCommand(file_commands, file_options);
}
