// SPDX-License-Identifier: MIT
/// @brief The steps that make telesphere-robot's parts (robot_assembly_parts.h).
#include "app/robot_assembly_parts.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <thread>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "robot/cameras/aravis_camera.h"
#include "robot/head/calibration_in_use.h"
#include "robot/stereo/ground_truth_log.h"
#include "robot/arm/head_arm_sim.h"
#include "robot/arm/head_arm_xarm.h"
#include "robot/head/head_loop.h"
#include "robot/video/preview_streamer.h"
#include "robot/services/recording_switch.h"
#include "robot/services/robot_control.h"
#include "robot/services/robot_health_reporter.h"
#include "robot/stereo/simulated_manipulator.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/stereo/true_camera_poses.h"
#include "robot/video/video_streamer.h"

namespace telesphere::app {

namespace {

bool hasStereoMount(const calib::SystemCalibration& c) {
  return c.cameras.size() == 2 && c.T_cam_l_cam_r && c.T_flange_cam_l;
}

}  // namespace

bool loadCalibrations(RobotAssembly::Parts& p, std::string* error) {
  const RobotOptions& o = p.options;
  auto loaded = calib::loadCalibrationFile(o.calib_path);
  if (!loaded) {
    *error = loaded.error().describe();
    return false;
  }
  p.calibration = *loaded;
  if (!hasStereoMount(p.calibration)) {
    *error = o.calib_path + ": needs two cameras, T_cam_l_cam_r and T_flange_cam_l (run telesphere-calib "
                            "intrinsics and handeye first)";
    return false;
  }
  p.true_calibration = p.calibration;
  if (o.true_calib_path.empty()) return true;
  auto loaded_true = calib::loadCalibrationFile(o.true_calib_path);
  if (!loaded_true) {
    *error = "--sim-truth: " + loaded_true.error().describe();
    return false;
  }
  p.true_calibration = *loaded_true;
  if (!hasStereoMount(p.true_calibration)) {
    *error = "--sim-truth " + o.true_calib_path + ": needs two cameras, T_cam_l_cam_r and T_flange_cam_l";
    return false;
  }
  return true;
}

bool makeManipulator(RobotAssembly::Parts& p, std::string* error) {
  const calib::SystemCalibration& truth = p.true_calibration;
  if (truth.T_robot_mount.has_value() != truth.T_wrist_marker.has_value()) {
    *error = "--sim-manipulator: the true calibration has only one of T_robot_mount and T_wrist_marker (give "
             "both or neither)";
    return false;
  }
  robot::stereo::SimulatedManipulatorConfig config;
  if (truth.T_robot_mount) config.mounting = {*truth.T_robot_mount, *truth.T_wrist_marker};
  p.manipulator = robot::stereo::SimulatedManipulator::create(config, error);
  if (!p.manipulator) *error = "--sim-manipulator: " + *error;
  return p.manipulator.has_value();
}

bool makeHead(RobotAssembly::Parts& p, int* exit_code, std::string* error) {
  robot::head::HeadControllerConfig controller_config;
  controller_config.geometry.T_flange_cam_l = *p.calibration.T_flange_cam_l;
  controller_config.geometry.T_cam_l_cam_r = *p.calibration.T_cam_l_cam_r;
  p.controller = std::make_unique<robot::head::HeadController>(controller_config);
  // Start at the nominal head pose so the first frames already look where the operator will.
  const auto ik = p.controller->kinematics().inverse(
      controller_config.T_robot_nom * controller_config.geometry.T_flange_head().inverse(),
      robot::arm::JointVector::Zero(), controller_config.ik);
  if (ik.status == robot::arm::IkResult::Status::kConverged) p.q_initial = ik.q;

  p.joints = std::make_unique<robot::head::JointStateBuffer>(controller_config.geometry);
  const RobotOptions& o = p.options;
  if (o.realArm()) {
    robot::arm::XArmOptions xarm;
    xarm.address = o.arm_address;
    xarm.command_port = o.arm_command_port;
    xarm.report_port = o.arm_report_port;
    xarm.normal_report_port = o.arm_normal_report_port;
    if (o.arm_payload_kg >= 0) xarm.payload_kg = o.arm_payload_kg;
    if (o.arm_payload_com_mm.size() == 3)
      xarm.payload_com_mm = {o.arm_payload_com_mm[0], o.arm_payload_com_mm[1], o.arm_payload_com_mm[2]};
    if (o.arm_collision_sensitivity >= 0) xarm.collision_sensitivity = o.arm_collision_sensitivity;
    xarm.clear_errors = o.arm_clear_errors;
    xarm.nominal_q = p.q_initial;
    auto arm = robot::arm::XArmHeadArm::start(xarm, p.clock, error, [](const std::string& step) {
      std::fprintf(stderr, "telesphere-robot: xArm: %s\n", step.c_str());
    });
    if (!arm) {
      *error = "xArm at " + o.arm_address + ": " + *error;
      *exit_code = 2;
      return false;
    }
    p.arm_description = "xArm 6 at " + o.arm_address + " (firmware " + arm->stats().firmware + ")";
    p.arm = std::move(arm);
    return true;
  }
  robot::head::HeadGeometry true_geometry;
  true_geometry.T_flange_cam_l = *p.true_calibration.T_flange_cam_l;
  true_geometry.T_cam_l_cam_r = *p.true_calibration.T_cam_l_cam_r;
  robot::head::JointStateBufferConfig truth_config;
  truth_config.capacity = 8192;  // 8 s at 1 kHz
  p.truth = std::make_unique<robot::head::JointStateBuffer>(true_geometry, truth_config);
  robot::arm::SimulatedArmConfig arm_config;
  arm_config.q_initial = p.q_initial;
  arm_config.on_true_state = [truth = p.truth.get()](const robot::arm::JointState& s) { truth->push(s); };
  p.arm = std::make_unique<robot::arm::SimulatedArm>(p.clock, arm_config);
  p.arm_description = "simulated xArm 6";
  return true;
}

bool makeCameras(RobotAssembly::Parts& p, int* exit_code, std::string* error) {
  const RobotOptions& o = p.options;
  if (o.syntheticCameras()) {
    const Eigen::Isometry3d T_robot_cam_l0 =
        p.controller->kinematics().forward(p.q_initial) * *p.true_calibration.T_flange_cam_l;
    // With the real arm there is no truth but what it reports: the synthetic cameras render there.
    p.true_poses = std::make_unique<robot::stereo::TrueCameraPoses>(
        p.truth ? *p.truth : *p.joints, p.clock,
        std::array<Eigen::Isometry3d, 2>{T_robot_cam_l0, T_robot_cam_l0 * *p.true_calibration.T_cam_l_cam_r});
    robot::cameras::DefaultSceneLayout layout;
    if (p.manipulator)
      layout.marker_pose = [m = &*p.manipulator](std::int64_t t_ns) { return m->T_robot_marker(t_ns); };
    auto scene = std::make_shared<const robot::cameras::SyntheticScene>(robot::cameras::defaultScene(layout));
    // One trigger line for both: when rendering falls behind the frame rate they still expose the
    // same ticks, so every frame can pair.
    const auto trigger = std::make_shared<robot::cameras::SyntheticTrigger>();
    for (int index : {0, 1}) {
      const auto camera = calib::atResolution(p.true_calibration.cameras[std::size_t(index)], o.width, o.height, error);
      if (!camera) {
        *exit_code = 1;
        return false;
      }
      robot::cameras::SyntheticCameraOptions options;
      options.name = index == 0 ? "synthetic-left" : "synthetic-right";
      options.fps = o.fps;
      options.threads = o.render_threads;
      options.exposure_us = static_cast<std::uint32_t>(std::lround(o.exposure_ms * 1000.0));
      options.transfer_ns = std::llround(o.transfer_ms * 1e6);
      options.trigger = trigger;
      const robot::cameras::CameraSide side = index == 0 ? robot::cameras::CameraSide::kLeft : robot::cameras::CameraSide::kRight;
      (index == 0 ? p.left : p.right) = std::make_unique<robot::cameras::SyntheticCamera>(
          camera->camera, o.width, o.height, scene,
          [poses = p.true_poses.get(), side](std::int64_t t_ns) { return poses->at(side, t_ns); }, p.clock,
          options);
    }
  } else {
    for (auto [id, out] : {std::pair{&o.camera_left, &p.left}, std::pair{&o.camera_right, &p.right}}) {
      robot::cameras::AravisCameraOptions options;
      options.device_id = *id;
      options.frame_rate_hz = o.fps;
      // A Bayer camera's raw mosaic goes to the encoder, which debayers it on its side's thread
      // straight into the planes it compresses (#34): no RGB image on the camera's thread.
      options.debayer = false;
      *out = std::make_unique<robot::cameras::AravisCamera>(options);
    }
  }
  for (robot::cameras::CameraSource* camera : {p.left.get(), p.right.get()}) {
    if (!camera->start(error)) {
      *error = "camera " + camera->name() + ": " + *error;
      *exit_code = 2;
      return false;
    }
  }
  return true;
}


}  // namespace telesphere::app
