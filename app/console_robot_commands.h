// SPDX-License-Identifier: MIT
/// @brief `telesphere-console status|control`: the supervisor's headless view of the robot and
///        its controls, for scripts that run a rig (issue #30).
///   status  --robot URL [--json] [--wait S]     health, arm, hold, recording, settings; exit 3
///                                               when the robot does not answer within --wait
///   control --robot URL stop | clear-fault | mode full6d|orientation3d|fixed | radius R
///                       | release-hold | record start NAME | record stop
///                                               prints the robot's reply; clear-fault waits
///                                               (--wait) for the arm's outcome
/// Exit codes: 0 ok; 1 bad arguments; 3 the robot did not answer; 5 the robot refused (its reason
/// is printed), or the arm's fault was not cleared.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "app/link_security_options.h"

namespace telesphere::app {

struct RobotCommandOptions {
  std::string robot = "tcp://127.0.0.1:5760";
  bool json = false;
  double wait_s = 10.0;
  std::vector<std::string> action;  ///< control: the words after `control`
  LinkSecurityOptions security;     ///< --keys DIR (a supervisor or viewer key) | --insecure
};

CLI::App* addStatusCommand(CLI::App& app, RobotCommandOptions& options);
CLI::App* addControlCommand(CLI::App& app, RobotCommandOptions& options);
int runStatusCommand(const RobotCommandOptions& options);
int runControlCommand(const RobotCommandOptions& options);

}  // namespace telesphere::app
