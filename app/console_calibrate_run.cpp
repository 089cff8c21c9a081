// SPDX-License-Identifier: MIT
/// @brief What every `telesphere-console calibrate` run shares (console_calibrate_command.h): the
///        robot's address, interrupts that release the head, waiting for the robot, reporting and
///        saving the result, applying it to the robot.
#include "app/console_calibrate_command.h"

#include <csignal>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <algorithm>

#include "calib/aprilgrid.h"
#include "calib/calibration_file.h"
#include "console/calibration/intrinsics_procedure.h"
#include "console/calibration/model_comparison.h"
#include "robot/link/link_client.h"

namespace telesphere::app {

bool parseRobotEndpoint(std::string text, link::LinkEndpoints* endpoints) {
  if (text.rfind("tcp://", 0) == 0) text = text.substr(6);
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 >= text.size() || colon + 6 < text.size()) return false;
  const std::string host = text.substr(0, colon), port = text.substr(colon + 1);
  if (host.find('/') != std::string::npos ||
      !std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  endpoints->host = host;
  endpoints->base_port = std::stoi(port);
  return endpoints->base_port >= 1 && endpoints->base_port <= 65532;
}

namespace {
std::atomic<bool> g_interrupted{false};
extern "C" void onCalibrateSignal(int) { g_interrupted = true; }
}  // namespace

const std::atomic<bool>* installInterruptHandlers() {
  std::signal(SIGINT, onCalibrateSignal);
  std::signal(SIGTERM, onCalibrateSignal);
  return &g_interrupted;
}

int interruptedOr(int code) {
  if (!g_interrupted.load()) return code;
  std::cerr << "telesphere-console calibrate: interrupted: stopped and released the head\n";
  return 130;
}

bool robotAnswers(console::calibration::CalibrationRobot& robot, const std::string& endpoint) {
  if (robot.headPose(std::chrono::seconds(10))) return true;
  std::cerr << "telesphere-console calibrate: the robot never answered at " << endpoint
            << " within 10 s (is telesphere-robot running?)\n";
  return false;
}

int reportAndSave(const CalibrateCommandOptions& o, const nlohmann::ordered_json& figures,
                  const std::function<void(const nlohmann::ordered_json&)>& print, bool done, const std::string& error,
                  const std::optional<calib::SystemCalibration>& calibration, calib::CalibrationFormat format) {
  if (o.json) {
    std::cout << figures.dump(2) << '\n';
  } else {
    print(figures);
  }
  if (!done || !calibration) {
    std::cerr << "telesphere-console calibrate: " << error << '\n';
    return 2;
  }
  if (auto e = calib::saveCalibrationFile(*calibration, o.out, format)) {
    std::cerr << "telesphere-console calibrate: " << e->describe() << '\n';
    return 1;
  }
  std::cerr << "telesphere-console calibrate: wrote " << o.out << '\n';
  return 0;
}

int applyToRobot(console::calibration::CalibrationRobot& robot, const calib::SystemCalibration& result,
                 console::calibration::MeasuredParts parts, const std::string& source) {
  std::string error;
  const auto in_use = robot.calibrationInUse(&error);
  if (!in_use) {
    std::cerr << "telesphere-console calibrate: not applied: the robot's calibration: " << error << '\n';
    return 4;
  }
  const auto current = calib::parseCalibration(in_use->yaml(), "the robot's calibration");
  if (!current) {
    std::cerr << "telesphere-console calibrate: not applied: " << current.error().describe() << '\n';
    return 4;
  }
  const calib::SystemCalibration next = console::calibration::withMeasured(*current, result, parts);
  for (const auto& d : console::calibration::differences(*current, next)) {
    if (d.value > 0) std::fprintf(stderr, "telesphere-console calibrate: change %s %.3f %s %s\n", d.what.c_str(), d.value, d.unit.c_str(), d.detail.c_str());
  }
  const auto applied = robot.applyCalibration(next, source, &error);
  if (!applied) {
    std::cerr << "telesphere-console calibrate: not applied: " << error << '\n';
    return 4;
  }
  std::cerr << "telesphere-console calibrate: applied: the robot uses calibration generation " << applied->generation()
            << " (was " << in_use->generation() << ")\n";
  if (!applied->saved_to().empty())
    std::cerr << "telesphere-console calibrate: saved on the robot to " << applied->saved_to() << '\n';
  else
    std::cerr << "telesphere-console calibrate: warning: not saved on the robot"
              << (applied->save_error().empty() ? " (start it with --calib-save FILE)" : ": " + applied->save_error())
              << ": a restart goes back to its --calib file (keep the file written here)\n";
  return 0;
}

}  // namespace telesphere::app
