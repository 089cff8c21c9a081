// SPDX-License-Identifier: MIT
/// @brief What telesphere-robot wires (RobotAssembly::Parts) and the steps that make its parts:
///        the calibrations, the manipulator, the head (arm, controller, buffers) and the cameras
///        (robot_assembly_parts.cpp); robot_assembly.cpp builds and runs them in order.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "app/robot_assembly.h"
#include "robot/link/media/media_sender.h"
#include "calib/system_calibration.h"
#include "robot/arm/head_arm.h"
#include "robot/cameras/camera_source.h"
#include "robot/clock/clock.h"
#include "robot/head/calibration_in_use.h"
#include "robot/head/head_controller.h"
#include "robot/head/head_loop.h"
#include "robot/head/joint_state_buffer.h"
#include "robot/link/link_server.h"
#include "robot/services/recording_switch.h"
#include "robot/services/robot_control.h"
#include "robot/services/robot_health_reporter.h"
#include "robot/stereo/ground_truth_log.h"
#include "robot/stereo/simulated_manipulator.h"
#include "robot/stereo/stereo_pairer.h"
#include "robot/stereo/stereo_still.h"
#include "robot/stereo/true_camera_poses.h"
#include "robot/telemetry/telemetry_batcher.h"
#include "robot/video/preview_streamer.h"
#include "robot/video/video_streamer.h"

namespace telesphere::app {

/// In construction order; destroyed in reverse (each part outlives the parts that use it).
struct RobotAssembly::Parts {
  RobotOptions options;
  robot::clock::SteadyClock clock;
  calib::SystemCalibration calibration, true_calibration;
  std::optional<robot::stereo::SimulatedManipulator> manipulator;  ///< carries the wrist marker (hand-eye)
  robot::head::JointStateBuffer manipulator_reports{robot::head::HeadGeometry{}};
  std::unique_ptr<robot::head::HeadController> controller;
  robot::arm::JointVector q_initial = robot::arm::JointVector::Zero();
  /// The simulated arm's noise-free joints at every physics step (null with a real arm).
  std::unique_ptr<robot::head::JointStateBuffer> truth;
  std::unique_ptr<robot::arm::HeadArm> arm;  ///< SimulatedArm or XArmHeadArm
  std::string arm_description;          ///< for the console's health view
  std::unique_ptr<robot::head::JointStateBuffer> joints;  ///< the arm's reports, with the calibration in use
  std::unique_ptr<link::LinkServer> server;
  std::unique_ptr<link::media::MediaSender> media;  ///< the UDP media path (null: --no-media)
  std::unique_ptr<robot::services::RecordingSwitch> recording;  ///< --record, --record-dir, the console's requests
  std::unique_ptr<robot::head::CalibrationInUse> calibration_in_use;
  robot::telemetry::TelemetryBatcher telemetry;
  std::unique_ptr<robot::head::HeadLoop> loop;
  std::unique_ptr<robot::stereo::TrueCameraPoses> true_poses;
  std::unique_ptr<robot::cameras::CameraSource> left, right;
  std::unique_ptr<robot::stereo::StereoPairSource> pairs;
  std::unique_ptr<robot::video::PreviewStreamer> preview;
  std::unique_ptr<robot::stereo::GroundTruthLog> truth_log;
  std::unique_ptr<robot::stereo::StereoStillTaker> stills;
  std::unique_ptr<robot::video::VideoStreamer> video;
  std::unique_ptr<robot::services::RobotControl> control;
  std::unique_ptr<robot::services::RobotHealthReporter> health;
};

/// Loads and checks the calibration in use and the true one (the simulation's); false with the reason.
bool loadCalibrations(RobotAssembly::Parts& p, std::string* error);
/// The manipulator with the wrist marker, at the true calibration's mounting when it has one.
bool makeManipulator(RobotAssembly::Parts& p, std::string* error);
/// The head loop: the arm (simulated, or the real xArm started and at the nominal joints),
/// controller, joint-state buffers (reported, and with the simulated arm the truth). False with
/// the reason and *exit_code (2: the real arm could not start).
bool makeHead(RobotAssembly::Parts& p, int* exit_code, std::string* error);
/// Synthetic cameras (rendering at the arm's true pose) or GenICam cameras; started. False with
/// the reason and *exit_code.
bool makeCameras(RobotAssembly::Parts& p, int* exit_code, std::string* error);

}  // namespace telesphere::app
