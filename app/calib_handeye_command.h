// SPDX-License-Identifier: MIT
/// @brief `telesphere-calib handeye --samples FILE --calib FILE --out FILE`: T_flange_cam_l,
///        T_robot_mount and T_wrist_marker (paper eqs. 1–3) from a sample file
///        (calib/hand_eye_samples.h), the cameras' intrinsics from --calib, whose T_flange_cam_l
///        is also a start of the solve. Exit codes: 0 written, 1 bad files, 2 the solve failed
///        (the reason is printed).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace telesphere::app {

struct HandEyeCommandOptions {
  std::string samples, calib, out, format = "telesphere";
};

CLI::App* addHandEyeCommand(CLI::App& app, HandEyeCommandOptions& options);
int runHandEyeCommand(const HandEyeCommandOptions& options);

}  // namespace telesphere::app
