// SPDX-License-Identifier: MIT
/// @brief `telesphere-console calibrate handeye --auto` (see console_calibrate_command.h): the
///        hand-eye calibration of console/calibration/hand_eye_procedure.h, headless. Prints the
///        figures (--json: JSON on stdout): samples, stills refused, the three transforms with
///        standard deviations, per-sample residuals, accuracy against sample count along the
///        way, and the time from the first sample to the result.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/console_calibrate_command.h"
#include "calib/calibration_file.h"
#include "calib/target_detection.h"
#include "console/calibration/hand_eye_procedure.h"
#include "robot/link/link_client.h"

namespace telesphere::app {
namespace {

nlohmann::ordered_json poseJson(const Eigen::Isometry3d& T, const calib::PoseStddev& sd) {
  const Eigen::Quaterniond q(T.linear());
  nlohmann::ordered_json j;
  j["t_m"] = {T.translation().x(), T.translation().y(), T.translation().z()};
  j["q_xyzw"] = {q.x(), q.y(), q.z(), q.w()};
  if (sd.valid) {
    j["sigma_t_mm"] = {sd.translation_m.x() * 1e3, sd.translation_m.y() * 1e3, sd.translation_m.z() * 1e3};
    j["sigma_r_deg"] = {sd.rotation_deg.x(), sd.rotation_deg.y(), sd.rotation_deg.z()};
  }
  return j;
}

nlohmann::ordered_json handEyeFiguresOf(const console::calibration::HandEyeOutcome& out) {
  nlohmann::ordered_json j;
  j["done"] = out.done;
  j["error"] = out.error;
  j["done_rule"] = out.rule_text;
  j["stills"] = out.stills;
  j["stills_refused"] = out.refused;
  j["stills_too_close"] = out.too_close;
  j["outliers_removed"] = out.outliers_removed;
  j["first_sample_to_result_s"] = out.first_sample_to_result_s;
  j["total_s"] = out.total_s;
  j["head_returned"] = out.head_returned;
  if (!out.head_return_error.empty()) j["head_return_error"] = out.head_return_error;
  j["samples"] = out.collector ? out.collector->samples().size() : 0;
  if (out.collector) {
    const calib::HandEyeIdentifiability d = out.collector->diversity();
    j["head_axis_spread_deg"] = d.head_axis_spread_deg;
    j["wrist_axis_spread_deg"] = d.wrist_axis_spread_deg;
    if (const auto& r = out.collector->result()) {
      j["rms_px"] = {{"cam_l", r->rms_px_l}, {"cam_r", r->rms_px_r}};
      j["T_flange_cam_l"] = poseJson(r->T_flange_cam_l, r->stddev[0]);
      j["T_robot_mount"] = poseJson(r->T_robot_mount, r->stddev[1]);
      j["T_wrist_marker"] = poseJson(r->T_wrist_marker, r->stddev[2]);
      j["sample_rms_px"] = nlohmann::ordered_json::array();
      for (double rms : out.collector->sampleRmsPx()) j["sample_rms_px"].push_back(std::isfinite(rms) ? rms : -1.0);
    }
  }
  j["history"] = nlohmann::ordered_json::array();
  for (const auto& step : out.history) {
    nlohmann::ordered_json s{{"samples", step.samples}, {"elapsed_s", step.elapsed_s}, {"ok", step.ok}};
    if (step.ok) {
      s["rms_px"] = step.rms_px;
      s["T_flange_cam_l"] = poseJson(step.result.T_flange_cam_l, step.result.stddev[0]);
      s["T_robot_mount"] = poseJson(step.result.T_robot_mount, step.result.stddev[1]);
    } else {
      s["error"] = step.error;
    }
    j["history"].push_back(s);
  }
  j["unmet"] = out.check.unmet;
  return j;
}

void printHandEyeFigures(const nlohmann::ordered_json& j) {
  std::printf("done rule: %s\n", j["done_rule"].get<std::string>().c_str());
  std::printf("stills %d: samples kept %d, refused %d, too close %d; outliers removed %d\n", j["stills"].get<int>(),
              j["samples"].get<int>(), j["stills_refused"].get<int>(), j["stills_too_close"].get<int>(),
              j["outliers_removed"].get<int>());
  if (j.contains("head_axis_spread_deg"))
    std::printf("rotation axes spread: head %.1f°, wrist %.1f°\n", j["head_axis_spread_deg"].get<double>(),
                j["wrist_axis_spread_deg"].get<double>());
  if (j.contains("rms_px")) {
    std::printf("RMS cam_l %.3f px, cam_r %.3f px\n", j["rms_px"]["cam_l"].get<double>(), j["rms_px"]["cam_r"].get<double>());
    for (const char* name : {"T_flange_cam_l", "T_robot_mount", "T_wrist_marker"}) {
      const auto& p = j[name];
      std::printf("%-15s t = (%.4f, %.4f, %.4f) m", name, p["t_m"][0].get<double>(), p["t_m"][1].get<double>(),
                  p["t_m"][2].get<double>());
      if (p.contains("sigma_t_mm"))
        std::printf(" ± (%.2f, %.2f, %.2f) mm, rotation σ (%.3f, %.3f, %.3f)°", p["sigma_t_mm"][0].get<double>(),
                    p["sigma_t_mm"][1].get<double>(), p["sigma_t_mm"][2].get<double>(), p["sigma_r_deg"][0].get<double>(),
                    p["sigma_r_deg"][1].get<double>(), p["sigma_r_deg"][2].get<double>());
      std::printf("\n");
    }
  }
  std::printf("time from the first sample to the result: %.1f s (whole run %.1f s)\n",
              j["first_sample_to_result_s"].get<double>(), j["total_s"].get<double>());
}

}  // namespace

CLI::App* addHandEyeSubcommand(CLI::App& calibrate, CalibrateCommandOptions& o) {
  CLI::App* handeye = calibrate.add_subcommand(
      "handeye", "T_flange_cam_l, T_robot_mount and T_wrist_marker (paper eqs. 1–3): the head runs the sinusoidal "
                 "pattern while the manipulator moves its wrist marker in view");
  handeye->add_flag("--auto", o.automatic, "drive the robot and take samples until the done rule holds")->required();
  handeye->add_option("--robot", o.robot, "the robot's link endpoint (tcp://HOST:BASEPORT)")->capture_default_str();
  addLinkSecurityOptions(*handeye, o.security, "a supervisor key pair and the robot's .pub");
  handeye->add_option("--calib", o.calib, "calibration with both cameras' intrinsics and T_cam_l_cam_r (held fixed)")
      ->required()->check(CLI::ExistingFile);
  handeye->add_option("--out", o.out, "calibration file to write (--calib with the three transforms)")->required();
  handeye->add_option("--format", o.format, "telesphere, kalibr or basalt")->capture_default_str();
  handeye->add_option("--marker-dictionary", o.marker_dictionary, "ArUco dictionary of the wrist marker")
      ->capture_default_str();
  handeye->add_option("--marker-id", o.marker_id, "id of the wrist marker")->capture_default_str()->check(CLI::Range(0, 999));
  handeye->add_option("--marker-size", o.marker_size_m, "edge of the wrist marker, m")
      ->capture_default_str()->check(CLI::Range(0.005, 2.0));
  handeye->add_option("--pattern-deg", o.pattern_deg, "yaw amplitude of the head pattern, deg (0: the head holds still)")
      ->capture_default_str()->check(CLI::Range(0.0, 30.0));
  handeye->add_option("--min-samples", o.min_samples, "the done rule's number of samples")
      ->capture_default_str()->check(CLI::Range(5, 1000));
  handeye->add_option("--max-samples", o.max_samples, "give up after keeping this many samples")
      ->capture_default_str()->check(CLI::Range(5, 1000));
  handeye->add_option("--time-limit", o.time_limit_s, "give up after this many seconds")
      ->capture_default_str()->check(CLI::Range(1.0, 36000.0));
  handeye->add_flag("--json", o.json, "print the figures as JSON on stdout (the log stays on stderr)");
  handeye->add_flag("--apply", o.apply, "then make the robot use T_flange_cam_l live (exit 4 if refused)");
  return handeye;
}

int runHandEyeCalibrate(const CalibrateCommandOptions& o, const link::LinkEndpoints& endpoints) {
  const auto bad = [](const std::string& message) {
    std::cerr << "telesphere-console calibrate handeye: " << message << '\n';
    return 1;
  };
  const auto format = calib::parseFormatName(o.format);
  if (!format) return bad("--format '" + o.format + "': telesphere, kalibr or basalt");
  const auto dictionaries = calib::arucoDictionaryNames();
  if (std::find(dictionaries.begin(), dictionaries.end(), o.marker_dictionary) == dictionaries.end())
    return bad("--marker-dictionary '" + o.marker_dictionary + "' is not an ArUco dictionary (e.g. DICT_4X4_50)");
  auto cameras = calib::loadCalibrationFile(o.calib);
  if (!cameras) return bad(cameras.error().describe());
  if (cameras->cameras.size() != 2 || !cameras->T_cam_l_cam_r)
    return bad(o.calib + ": needs both cameras and T_cam_l_cam_r (run calibrate intrinsics first)");

  console::calibration::HandEyeProcedureOptions options;
  options.cameras = *cameras;
  options.marker = {o.marker_dictionary, o.marker_id, o.marker_size_m};
  options.pattern_amplitude_deg = o.pattern_deg;
  options.collector.rule.min_samples = o.min_samples;
  options.max_samples = o.max_samples;
  options.time_limit = std::chrono::seconds(static_cast<long>(o.time_limit_s));
  options.log = [](const std::string& line) { std::cerr << "calibrate: " << line << '\n'; };
  options.cancel = installInterruptHandlers();

  link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
  console::calibration::CalibrationRobot robot(client, "hand-eye wizard (headless)");
  if (!robotAnswers(robot, o.robot)) return 3;
  const auto outcome = console::calibration::runHandEyeAuto(robot, options);
  if (options.cancel->load()) return interruptedOr(2);
  const int code = reportAndSave(o, handEyeFiguresOf(outcome), printHandEyeFigures, outcome.done, outcome.error,
                                 outcome.calibration, *format);
  if (code != 0 || !o.apply) return code;
  return applyToRobot(robot, *outcome.calibration, console::calibration::MeasuredParts::kHandEye,
                      "hand-eye wizard (headless), " +
                          std::to_string(outcome.collector ? outcome.collector->samples().size() : 0) + " samples, " + o.out);
}

}  // namespace telesphere::app
