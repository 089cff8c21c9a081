// SPDX-License-Identifier: MIT
/// @brief `telesphere-calib handeye` (see calib_handeye_command.h).
#include "app/calib_handeye_command.h"

#include <cstdio>
#include <iostream>

#include "app/calib_cli_io.h"
#include "calib/hand_eye_samples.h"
#ifdef TELESPHERE_CALIB_HAS_ROBOT
#include "robot/arm/xarm6_kinematics.h"
#endif

namespace telesphere::app {
namespace {

/// The head arm's forward kinematics for sample files with joint angles (q_head): the xArm 6
/// model of robot/arm/xarm6_kinematics.h when the robot library is part of the build.
calib::HeadArmForwardKinematics headArmForwardKinematics() {
#ifdef TELESPHERE_CALIB_HAS_ROBOT
  return [kinematics = robot::arm::Xarm6Kinematics()](const std::vector<double>& q, std::string* error)
             -> std::optional<Eigen::Isometry3d> {
    if (q.size() != static_cast<std::size_t>(robot::arm::Xarm6Kinematics::kDof)) {
      *error = "expected " + std::to_string(robot::arm::Xarm6Kinematics::kDof) +
               " xArm 6 joint angles (rad), got " + std::to_string(q.size());
      return std::nullopt;
    }
    const robot::arm::JointVector joints = Eigen::Map<const robot::arm::JointVector>(q.data());
    if (!kinematics.withinLimits(joints, 1e-6)) {
      *error = "the joint angles are outside the xArm 6 joint limits";
      return std::nullopt;
    }
    return kinematics.forward(joints);
  };
#else
  return {};
#endif
}

}  // namespace

CLI::App* addHandEyeCommand(CLI::App& app, HandEyeCommandOptions& o) {
  CLI::App* handeye = app.add_subcommand(
      "handeye", "hand-eye calibration (T_flange_cam_l, T_robot_mount, T_wrist_marker) from a sample file");
  handeye->add_option("--samples", o.samples, "sample file (YAML, see calib/hand_eye_samples.h)")
      ->required()
      ->check(CLI::ExistingFile);
  handeye->add_option("--calib", o.calib, "calibration with the cameras' intrinsics (any format)")
      ->required()
      ->check(CLI::ExistingFile);
  handeye->add_option("--out", o.out, "output calibration file (the input plus the hand-eye transforms)")
      ->required();
  handeye->add_option("--format", o.format, "output format")
      ->check(CLI::IsMember({"telesphere", "kalibr", "basalt"}))
      ->capture_default_str();
  return handeye;
}

int runHandEyeCommand(const HandEyeCommandOptions& o) {
  auto system = loadCalibrationOrSay(o.calib);
  if (!system) return 1;
  const auto file = calib::loadHandEyeSamples(o.samples, progressLine, headArmForwardKinematics());
  if (!file) {
    std::cerr << "telesphere-calib: " << file.error().describe() << "\n";
    return 1;
  }
  calib::HandEyeOptions options;
  options.progress = progressLine;
  // The file's T_flange_cam_l is a second start for the solve (and the only one below
  // kClosedFormMinSamples samples), as in the console's wizard.
  options.T_flange_cam_l_guess = system->T_flange_cam_l;
  const auto result = calib::calibrateHandEye(*system, file->marker_size, file->samples, options);
  if (!result) {
    std::cerr << "telesphere-calib: " << result.failure().message << "\n";
    return 2;
  }
  std::printf("hand-eye: %d samples, RMS cam_l %.4f px, cam_r %.4f px; rotation axes spread head %.1f deg, wrist %.1f deg\n",
              result->samples_used, result->rms_px_l, result->rms_px_r,
              result->identifiability.head_axis_spread_deg, result->identifiability.wrist_axis_spread_deg);
  const std::pair<const char*, const Eigen::Isometry3d*> transforms[] = {
      {"T_flange_cam_l", &result->T_flange_cam_l},
      {"T_robot_mount", &result->T_robot_mount},
      {"T_wrist_marker", &result->T_wrist_marker}};
  for (const auto& [name, T] : transforms)
    std::cout << name << ":\n" << T->matrix() << "\n";
  system->T_flange_cam_l = result->T_flange_cam_l;
  system->T_robot_mount = result->T_robot_mount;
  system->T_wrist_marker = result->T_wrist_marker;
  if (auto error = calib::saveCalibrationFile(*system, o.out, *calib::parseFormatName(o.format))) {
    std::cerr << "telesphere-calib: " << error->describe() << "\n";
    return 1;
  }
  std::cerr << "wrote " << o.out << " (" << o.format << ")\n";
  return 0;
}

}  // namespace telesphere::app
