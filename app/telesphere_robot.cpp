// SPDX-License-Identifier: MIT
/// @brief telesphere-robot: the robot side (DESIGN.md §1, §4, §5): cameras, head arm and the link
///        server, wired by RobotAssembly (app/robot_assembly.h) from RobotOptions
///        (app/robot_options.h).
///
/// With --sim (the default) the arm is the simulated xArm 6
/// and the cameras are synthetic, rendering the default scene through the true calibration
/// (--sim-truth, by default the one the robot uses) at the arm's true pose at the middle of each
/// exposure, delivered after exposure/2 + transfer; frames are stamped, as on the real robot,
/// with the pose the joint-state buffer interpolates. --truth-out writes that truth per frame.
/// --sim-manipulator adds the manipulator carrying the wrist marker (hand-eye calibration).
/// With --camera-left/--camera-right the cameras are GenICam cameras through Aravis. With --arm
/// xarm --arm-address IP the head arm is a real xArm 6 (robot/arm/xarm/README.md: the lab's steps).
/// --record FILE records everything on the link (MCAP); --replay FILE serves such a recording
/// instead of a robot (app/robot_replay.h).
/// Stops cleanly on SIGINT/SIGTERM or after --duration seconds; prints statistics periodically.
/// Exit codes: 0 ok, 1 bad arguments or files, 2 the arm, a camera or the link could not start.
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <iostream>

#include "app/robot_assembly.h"
#include "app/robot_options.h"
#include "app/robot_replay.h"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"telesphere-robot: cameras, head arm and link server of the robot side"};
  telesphere::app::RobotOptions options;
  telesphere::app::addRobotOptions(app, options);
  CLI11_PARSE(app, argc, argv);
  std::string error;
  if (!telesphere::app::checkRobotOptions(options, &error)) {
    std::cerr << "telesphere-robot: " << error << '\n';
    return 1;
  }
  const telesphere::app::InsecureLinkWarning insecure_warning(options.security.insecure, "telesphere-robot");
  if (options.replay()) {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    return telesphere::app::runReplay(options, g_stop);
  }
  int exit_code = 0;
  const auto robot = telesphere::app::RobotAssembly::build(options, &exit_code, &error);
  if (!robot) {
    std::cerr << "telesphere-robot: " << error << '\n';
    return exit_code;
  }
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::cerr << "telesphere-robot: " << robot->describe() << '\n';
  const std::uint64_t frames = robot->run(g_stop);
  std::cerr << "telesphere-robot: stopped after " << frames << " frames\n";
  return 0;
}
