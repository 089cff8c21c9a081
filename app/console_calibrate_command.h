// SPDX-License-Identifier: MIT
/// @brief `telesphere-console calibrate intrinsics|handeye --auto`: the intrinsic and stereo
///        calibration (console/calibration/intrinsics_procedure.h) and the hand-eye calibration
///        (console/calibration/hand_eye_procedure.h; app/console_calibrate_handeye.cpp) run
///        headless against the live robot (issue #15), for labs that script their set-up and for
///        tests. It drives the head, takes stills until
///        the done rule holds, solves, writes the file and prints the figures (--json: as JSON on
///        stdout). With --apply the robot (and the XR app through it) then uses the result live:
///        only the part the procedure measured replaces the calibration in use
///        (console/calibration/calibration_change.h). Exit codes: 0 done and written (and
///        applied); 1 bad arguments or files; 2 the done rule cannot be met (the reason is
///        printed; no file is written); 3 the robot never answered; 4 written, but the robot
///        refused to apply it (its reason is printed); 130 interrupted (SIGINT or SIGTERM: the
///        procedure stops and the head is released before the exit).
#pragma once

#include <CLI/CLI.hpp>
#include <atomic>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "app/link_security_options.h"
#include "calib/calibration_file.h"
#include "console/calibration/calibration_change.h"
#include "console/calibration/calibration_robot.h"
#include "robot/link/link_endpoints.h"

namespace telesphere::app {

struct CalibrateCommandOptions {
  bool automatic = false;
  std::string robot = "tcp://127.0.0.1:5760";
  LinkSecurityOptions security;  ///< --keys DIR (a supervisor key) | --insecure
  std::string out, format = "telesphere", model = "ds", initial, target, save_stills;
  int min_views = 20, max_views = 60;
  double max_focal_std_pct = 0.2;  ///< the done rule's σ(fx), σ(fy) bound, % of f
  bool json = false;
  bool compare_models = false;
  double tolerance_px = 1.0;
  // handeye
  std::string calib;  ///< intrinsics and T_cam_l_cam_r the solve holds fixed
  std::string marker_dictionary = "DICT_4X4_50";
  int marker_id = 0;
  double marker_size_m = 0.1;
  double pattern_deg = 20.0;
  int min_samples = 15, max_samples = 60;
  double time_limit_s = 900;
  bool apply = false;  ///< make the robot use the result (written first)
};

/// "tcp://HOST:PORT" or "HOST:PORT"; false when it is neither.
bool parseRobotEndpoint(std::string text, link::LinkEndpoints* endpoints);

/// Set by SIGINT and SIGTERM once installInterruptHandlers() ran: the procedures' cancel flag, so
/// an interrupted wizard releases the head before it exits (the lease would end it within 2 s).
const std::atomic<bool>* installInterruptHandlers();
/// Exit code and message for a run that ended: 130 when it was interrupted, else `code`.
int interruptedOr(int code);

/// Waits up to 10 s for the robot's first state; false (after saying so) when none came.
bool robotAnswers(console::calibration::CalibrationRobot& robot, const std::string& endpoint);

/// The end of a run: prints `figures` (JSON on stdout with --json, else through `print`), then
/// writes `calibration` to --out when `done`. The exit code: 0 written, 2 not done (`error`
/// said), 1 the file could not be written.
int reportAndSave(const CalibrateCommandOptions& options, const nlohmann::ordered_json& figures,
                  const std::function<void(const nlohmann::ordered_json&)>& print, bool done, const std::string& error,
                  const std::optional<calib::SystemCalibration>& calibration, calib::CalibrationFormat format);

/// --apply: puts the measured part of `result` into the robot's calibration in use. 0, or 4 with
/// the robot's reason said.
int applyToRobot(console::calibration::CalibrationRobot& robot, const calib::SystemCalibration& result,
                 console::calibration::MeasuredParts parts, const std::string& source);

/// `calibrate handeye` (app/console_calibrate_handeye.cpp).
CLI::App* addHandEyeSubcommand(CLI::App& calibrate, CalibrateCommandOptions& options);
int runHandEyeCalibrate(const CalibrateCommandOptions& options, const link::LinkEndpoints& endpoints);

/// Adds `calibrate` with its `intrinsics` and `handeye` subcommands to `app`.
CLI::App* addCalibrateCommand(CLI::App& app, CalibrateCommandOptions& options);
int runCalibrateCommand(const CLI::App& calibrate, const CalibrateCommandOptions& options);

}  // namespace telesphere::app
