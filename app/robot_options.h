// SPDX-License-Identifier: MIT
/// @brief telesphere-robot's options: what the command line sets, with the defaults of an embedded
///        run (simulated arm, synthetic cameras, the simulation calibration), and their checks.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "app/link_security_options.h"

namespace telesphere::app {

struct RobotOptions {
  std::string calib_path = TELESPHERE_SOURCE_DIR "/calib/data/sim_calibration.yaml";
  std::string calib_save;  ///< where every calibration applied live is saved (empty: not saved)
  int port = 5760;
  std::string size = "640x360";  ///< the synthetic cameras render in real time at this size
  int width = 640, height = 360;  ///< parsed from size by checkRobotOptions
  int still_timeout_ms = 800;
  double fps = 45.0;
  int quality = 90;
  std::string subsampling = "420";
  std::string codec = "mjpeg";   ///< mjpeg, h264, hevc (#34)
  double video_mbit = 20;        ///< H.264/HEVC target, both cameras together
  int key_frame_interval = 90;   ///< H.264/HEVC: pairs between key frames
  bool video_gpu = false;        ///< H.264/HEVC: NVENC first
  double duration_s = 0.0;
  double stats_period_s = 2.0;
  std::string camera_left, camera_right;  ///< Aravis device ids; empty: synthetic cameras
  bool auto_nominal = true;
  double sphere_radius = 1.0;
  std::string depth_proxy;  ///< the session's scene proxy from the start; empty: each XR app's own
  int render_threads = 2;
  int preview_width = 320;
  double preview_hz = 5.0;
  bool sim = false;           ///< the default anyway; explicit for scripts
  double exposure_ms = 8.0;   ///< the paper's cameras
  double transfer_ms = 10.0;  ///< the paper: about 10 ms over USB
  std::string true_calib_path;
  std::string truth_path;
  bool sim_manipulator = false;
  std::string arm = "sim";       ///< "sim" (simulated xArm 6) or "xarm" (the real one)
  std::string arm_address;       ///< the xArm controller's IPv4 address
  int arm_command_port = 502;    ///< its command port (the protocol simulator's may differ)
  int arm_report_port = 30003;   ///< its real-time report port
  int arm_normal_report_port = 30001;  ///< its normal report port (payload, sensitivities read back)
  double arm_payload_kg = -1;    ///< the head's mass on the flange (< 0: not set, the controller keeps its own)
  std::vector<double> arm_payload_com_mm;  ///< its centre of mass in the tool frame, x y z (mm)
  int arm_collision_sensitivity = -1;  ///< 0..5 (< 0: not set)
  bool arm_clear_errors = false; ///< clear the controller's errors at start-up (the supervisor asks)
  std::string record_path;       ///< record the session (everything on the link) to this MCAP file
  std::string record_dir;        ///< where the console's and the study's recordings go (empty: none)
  std::string record_compression = "none";  ///< chunk compression: none, lz4, zstd
  std::string replay_path;       ///< serve this recording on the link instead of a robot
  double replay_rate = 1.0;      ///< --replay: pace (2: twice as fast)
  bool replay_loop = false;      ///< --replay: start again at the end
  bool media = true;             ///< the UDP media path on port + 4 (DESIGN.md §9)
  LinkSecurityOptions security;  ///< --keys DIR | --insecure (DESIGN.md §10)
  link::trust::LinkCredentials credentials;  ///< what --keys holds (checkRobotOptions reads it)
  double media_cap_mbit = 0;     ///< the supervisor's cap on its rate (0: none)
  double media_start_mbit = 8;   ///< its rate before the first reports

  bool syntheticCameras() const { return camera_left.empty(); }
  bool realArm() const { return arm == "xarm"; }
  bool replay() const { return !replay_path.empty(); }
};

/// Declares every option on `app`, bound to `options`.
void addRobotOptions(CLI::App& app, RobotOptions& options);

/// The checks across options (and the size's parse into width × height); false with the message.
bool checkRobotOptions(RobotOptions& options, std::string* error);

}  // namespace telesphere::app
