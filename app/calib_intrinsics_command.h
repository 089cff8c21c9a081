// SPDX-License-Identifier: MIT
/// @brief `telesphere-calib intrinsics --images DIR [--images-right DIR] --target aprilgrid.yaml
///        --model ds --out FILE`: a camera's (or the stereo pair's) intrinsics and T_cam_l_cam_r
///        from folders of images of a kalibr Aprilgrid, with a report JSON; and `telesphere-calib
///        report --report FILE [--coverage PREFIX]`: that report's kalibr-style summary and
///        coverage pictures. Exit codes: 0 written, 1 bad arguments or files, 2 the solve failed.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace telesphere::app {

struct IntrinsicsCommandOptions {
  std::string images, images_right, target, model = "ds", out, format = "telesphere", report;
  int min_tags = 4;
};

CLI::App* addIntrinsicsCommand(CLI::App& app, IntrinsicsCommandOptions& options);
int runIntrinsicsCommand(const IntrinsicsCommandOptions& options);

struct ReportCommandOptions {
  std::string report, coverage_prefix;
};

CLI::App* addReportCommand(CLI::App& app, ReportCommandOptions& options);
int runReportCommand(const ReportCommandOptions& options);

}  // namespace telesphere::app
