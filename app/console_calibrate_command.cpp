// SPDX-License-Identifier: MIT
/// @brief `telesphere-console calibrate intrinsics` and the command line of `calibrate` (see
///        console_calibrate_command.h); what every run shares: console_calibrate_run.cpp.
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

namespace {

nlohmann::ordered_json figuresOf(const console::calibration::IntrinsicsOutcome& out) {
  nlohmann::ordered_json j;
  j["done"] = out.done;
  j["error"] = out.error;
  j["done_rule"] = out.rule_text;
  j["poses_planned"] = out.poses_planned;
  j["poses_visited"] = out.poses_visited;
  j["poses_refused"] = out.poses_refused;
  j["poses_unsettled"] = out.poses_unsettled;
  j["fallback_poses_held"] = out.fallback_poses_held;
  j["poses_held_from_start"] = out.poses_held_from_start;
  j["stills"] = out.stills;
  j["samples_rejected"] = out.samples_rejected;
  j["first_sample_to_result_s"] = out.first_sample_to_result_s;
  j["total_s"] = out.total_s;
  j["head_returned"] = out.head_returned;
  if (!out.head_return_error.empty()) j["head_return_error"] = out.head_return_error;
  if (out.collector) {
    j["samples"] = out.collector->samples().size();
    j["joint_views"] = out.collector->jointViews();
    for (int c = 0; c < 2; ++c) {
      const calib::ViewCoverage& cov = out.collector->coverage(c);
      j["coverage"][c == 0 ? "cam_l" : "cam_r"] = {{"grid", cov.gridCoverage()},
                                                   {"polar_bins_reached", cov.polarBinsReached()},
                                                   {"polar_bins", cov.polarBins()},
                                                   {"image_max_polar_deg", cov.imageMaxPolarDeg()}};
    }
  }
  if (out.result) {
    for (const calib::CameraIntrinsicResult& cam : out.result->cameras) {
      nlohmann::ordered_json c;
      c["model"] = std::string(cam.calibration.camera.modelName());
      c["rms_px"] = cam.rms_px;
      c["views_used"] = cam.views_used;
      c["corners"] = cam.corners;
      c["width"] = cam.calibration.width;
      c["height"] = cam.calibration.height;
      const auto names = calib::GenericCamera::paramNames(cam.calibration.camera.modelName());
      const Eigen::VectorXd p = cam.calibration.camera.params();
      for (std::size_t i = 0; i < names.size(); ++i) {
        c["params"][std::string(names[i])] = p[Eigen::Index(i)];
        if (i < cam.param_stddev.size()) c["stddev"][std::string(names[i])] = cam.param_stddev[i];
      }
      c["degeneracy_warning"] = cam.degeneracy_warning;
      j["cameras"][cam.calibration.label] = c;
    }
    if (out.result->T_cam_l_cam_r) {
      const Eigen::Isometry3d& T = *out.result->T_cam_l_cam_r;
      const Eigen::Quaterniond q(T.linear());
      j["T_cam_l_cam_r"] = {{"t_m", {T.translation().x(), T.translation().y(), T.translation().z()}},
                            {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
      const calib::PoseStddev& sd = out.result->T_cam_l_cam_r_stddev;
      if (sd.valid)
        j["T_cam_l_cam_r"]["stddev"] = {
            {"t_m", {sd.translation_m.x(), sd.translation_m.y(), sd.translation_m.z()}},
            {"r_deg", {sd.rotation_deg.x(), sd.rotation_deg.y(), sd.rotation_deg.z()}}};
    }
  }
  j["unmet"] = nlohmann::ordered_json::array();
  for (const auto* check : {&out.collection, &out.solve})
    for (const std::string& u : check->unmet) j["unmet"].push_back(u);
  return j;
}

void printFigures(const nlohmann::ordered_json& j) {
  std::printf("done rule: %s\n", j["done_rule"].get<std::string>().c_str());
  std::printf("poses planned %d, visited %d, refused %d (%d held from the start pose, %d with another pose), unsettled %d; stills %d; samples "
              "kept %d (joint %d), not kept %d\n",
              j["poses_planned"].get<int>(), j["poses_visited"].get<int>(), j["poses_refused"].get<int>(),
              j.value("poses_held_from_start", 0), j.value("fallback_poses_held", 0), j["poses_unsettled"].get<int>(), j["stills"].get<int>(), j.value("samples", 0), j.value("joint_views", 0),
              j["samples_rejected"].get<int>());
  if (j.contains("cameras")) {
    for (const auto& [label, c] : j["cameras"].items()) {
      std::printf("%s (%s, %dx%d): RMS %.3f px over %d views, %d corners\n", label.c_str(),
                  c["model"].get<std::string>().c_str(), c["width"].get<int>(), c["height"].get<int>(),
                  c["rms_px"].get<double>(), c["views_used"].get<int>(), c["corners"].get<int>());
      for (const auto& [name, value] : c["params"].items()) {
        const double sd = c.contains("stddev") && c["stddev"].contains(name) ? c["stddev"][name].get<double>() : NAN;
        std::printf("  %-6s %14.6f ± %.6f\n", name.c_str(), value.get<double>(), sd);
      }
    }
  }
  if (j.contains("T_cam_l_cam_r")) {
    const auto& T = j["T_cam_l_cam_r"];
    std::printf("T_cam_l_cam_r: t %.5f %.5f %.5f m", T["t_m"][0].get<double>(), T["t_m"][1].get<double>(),
                T["t_m"][2].get<double>());
    if (T.contains("stddev"))
      std::printf(" ± %.3f %.3f %.3f mm, rotation ± %.4f %.4f %.4f deg", T["stddev"]["t_m"][0].get<double>() * 1e3,
                  T["stddev"]["t_m"][1].get<double>() * 1e3, T["stddev"]["t_m"][2].get<double>() * 1e3,
                  T["stddev"]["r_deg"][0].get<double>(), T["stddev"]["r_deg"][1].get<double>(),
                  T["stddev"]["r_deg"][2].get<double>());
    std::printf("\n");
  }
  std::printf("time from the first sample to the result: %.1f s (whole run %.1f s)\n",
              j["first_sample_to_result_s"].get<double>(), j["total_s"].get<double>());
  if (j.contains("models")) {
    std::printf("\n| model | parameters | RMS px (worse camera) | views used | solve s | note |\n|---|---:|---:|---:|---:|---|\n");
    for (const auto& m : j["models"]) {
      std::printf("| %s | %d | %s | %d | %.2f | %s |\n", m["model"].get<std::string>().c_str(), m["parameters"].get<int>(),
                  m["ok"].get<bool>() ? std::to_string(m["rms_px"].get<double>()).substr(0, 6).c_str() : "—",
                  m["views_used"].get<int>(), m["solve_s"].get<double>(), m["message"].get<std::string>().c_str());
    }
    const std::string pre = j["preselected_model"].get<std::string>();
    std::printf("simplest model within %.2f px: %s\n", j["tolerance_px"].get<double>(),
                pre.empty() ? "none" : pre.c_str());
  }
}

}  // namespace

CLI::App* addCalibrateCommand(CLI::App& app, CalibrateCommandOptions& o) {
  CLI::App* calibrate = app.add_subcommand("calibrate", "calibrate from the live robot (headless)");
  calibrate->require_subcommand(1);
  CLI::App* intrinsics = calibrate->add_subcommand(
      "intrinsics", "both cameras' intrinsics and T_cam_l_cam_r: the robot turns the head so that a fixed Aprilgrid "
                    "covers the images out to the rim");
  intrinsics->add_flag("--auto", o.automatic, "drive the robot and take samples until the done rule holds")->required();
  intrinsics->add_option("--robot", o.robot, "the robot's link endpoint (tcp://HOST:BASEPORT)")->capture_default_str();
  addLinkSecurityOptions(*intrinsics, o.security, "a supervisor key pair and the robot's .pub");
  intrinsics->add_option("--out", o.out, "calibration file to write")->required();
  intrinsics->add_option("--format", o.format, "telesphere, kalibr or basalt")->capture_default_str();
  intrinsics->add_option("--model", o.model, "camera model: ds, eucm, kb4 or pinhole")->capture_default_str();
  intrinsics->add_option("--initial", o.initial,
                         "the calibration the robot runs with (plans the head poses; its hand-eye transforms are kept "
                         "in --out)")
      ->check(CLI::ExistingFile);
  intrinsics->add_option("--target", o.target, "kalibr Aprilgrid YAML (default: 6×6 tags of 88 mm, spacing 0.3)")
      ->check(CLI::ExistingFile);
  intrinsics->add_option("--min-views", o.min_views, "the done rule's number of samples")
      ->capture_default_str()->check(CLI::Range(3, 1000));
  intrinsics->add_option("--max-views", o.max_views,
                         "stop collecting at this many samples (below --min-views the done rule cannot be met)")
      ->capture_default_str()->check(CLI::Range(3, 1000));
  intrinsics->add_option("--max-focal-std", o.max_focal_std_pct,
                         "the done rule's bound on σ(fx), σ(fy), % of f: smaller asks for more views (more time)")
      ->capture_default_str()->check(CLI::Range(0.001, 10.0));
  intrinsics->add_option("--save-stills", o.save_stills,
                         "write every still (PNG, full resolution) and stills.csv with its verdict to this folder");
  intrinsics->add_flag("--compare-models", o.compare_models,
                       "also solve ds, eucm, kb4 and pinhole on the same samples and name the simplest within "
                       "--tolerance-px");
  intrinsics->add_option("--tolerance-px", o.tolerance_px, "the RMS a model must reach to be preselected, px")
      ->capture_default_str()->check(CLI::Range(0.01, 100.0));
  intrinsics->add_flag("--json", o.json, "print the figures as JSON on stdout (the log stays on stderr)");
  intrinsics->add_flag("--apply", o.apply,
                       "then make the robot and the XR app use the cameras and T_cam_l_cam_r live (exit 4 if refused)");
  addHandEyeSubcommand(*calibrate, o);
  return calibrate;
}

int runCalibrateCommand(const CLI::App& calibrate, const CalibrateCommandOptions& o) {
  const auto bad = [](const std::string& message) {
    std::cerr << "telesphere-console calibrate: " << message << '\n';
    return 1;
  };
  link::LinkEndpoints endpoints;
  if (!parseRobotEndpoint(o.robot, &endpoints)) return bad("--robot '" + o.robot + "' is not tcp://HOST:PORT");
  std::string error;
  auto credentials = linkCredentialsFrom(o.security, {link::trust::LinkRole::kSupervisor}, &error);
  if (!credentials) return bad(error);
  endpoints.credentials = std::move(*credentials);
  const InsecureLinkWarning insecure_warning(o.security.insecure, "telesphere-console calibrate");
  if (calibrate.get_subcommand("handeye")->parsed()) return runHandEyeCalibrate(o, endpoints);
  const auto format = calib::parseFormatName(o.format);
  if (!format) return bad("--format '" + o.format + "': telesphere, kalibr or basalt");
  const auto& models = calib::GenericCamera::modelNames();
  if (std::find(models.begin(), models.end(), o.model) == models.end()) {
    return bad("--model '" + o.model + "': ds, eucm, kb4 or pinhole");
  }
  console::calibration::IntrinsicsProcedureOptions options;
  options.model = o.model;
  options.rule.min_views = o.min_views;
  options.rule.max_focal_std_rel = o.max_focal_std_pct / 100.0;
  options.max_views = o.max_views;
  options.stills_dir = o.save_stills;
  if (!o.target.empty()) {
    auto grid = calib::loadAprilGrid(o.target);
    if (!grid) return bad(grid.error().describe());
    options.grid = *grid;
  }
  if (!o.initial.empty()) {
    auto initial = calib::loadCalibrationFile(o.initial);
    if (!initial) return bad(initial.error().describe());
    options.initial = *initial;
  }
  options.log = [](const std::string& line) { std::cerr << "calibrate: " << line << '\n'; };
  options.cancel = installInterruptHandlers();

  link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
  console::calibration::CalibrationRobot robot(client, "intrinsics wizard (headless)");
  if (!robotAnswers(robot, o.robot)) return 3;
  const auto outcome = console::calibration::runIntrinsicsAuto(robot, options);
  if (options.cancel->load()) return interruptedOr(2);
  nlohmann::ordered_json figures = figuresOf(outcome);
  if (o.compare_models && outcome.collector && !outcome.collector->samples().empty()) {
    std::cerr << "calibrate: comparing the camera models on the same samples…\n";
    const auto comparison = console::calibration::compareModels(*outcome.collector, options.grid, o.tolerance_px);
    for (const auto& fit : comparison.fits) {
      figures["models"].push_back({{"model", fit.model},
                                   {"ok", fit.ok},
                                   {"rms_px", fit.rms_px},
                                   {"parameters", fit.parameters},
                                   {"views_used", fit.views_used},
                                   {"solve_s", fit.solve_s},
                                   {"message", fit.message}});
    }
    figures["tolerance_px"] = o.tolerance_px;
    figures["preselected_model"] = comparison.preselected.value_or("");
  }
  const int code = reportAndSave(o, figures, printFigures, outcome.done, outcome.error, outcome.calibration, *format);
  if (code != 0 || !o.apply) return code;
  return applyToRobot(robot, *outcome.calibration, console::calibration::MeasuredParts::kCameras,
                      "intrinsics wizard (headless), " + std::to_string(outcome.collector ? outcome.collector->samples().size() : 0) +
                          " views, " + o.out);
}

}  // namespace telesphere::app
