// SPDX-License-Identifier: MIT
#include "app/robot_options.h"

#include <cstdio>
#include <cstdlib>

namespace telesphere::app {

void addRobotOptions(CLI::App& app, RobotOptions& o) {
  app.add_flag("--sim", o.sim, "simulated arm and synthetic cameras (the default)");
  addLinkSecurityOptions(app, o.security,
                         "the robot's key pair (role robot) and allowed/, the .pub of every peer it lets in (read again "
                         "when it changes)");
  app.add_option("--calib-save", o.calib_save,
                 "save every calibration the console applies or reverts to live here (our YAML), so that a restart "
                 "with --calib FILE keeps it (default: not saved; the console warns)");
  app.add_option("--calib", o.calib_path, "system calibration (YAML, kalibr camchain or Basalt JSON)")
      ->capture_default_str();
  app.add_option("--port", o.port,
                 "link base port (frames, state, uplink, control: port..port+3; the UDP media path: port+4)")
      ->capture_default_str()->check(CLI::Range(1024, 65531));
  app.add_flag("!--no-media", o.media,
               "no UDP media path on port+4 (frames then go over the ZeroMQ link only, at the nominal settings)");
  app.add_option("--media-cap-mbit", o.media_cap_mbit,
                 "cap on the media path's rate, Mbit/s (0: none, the link's estimate decides; else at least 0.5, "
                 "the rate controller's floor; the console can change it)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100000.0))
      ->check(CLI::Validator(
          [](std::string& value) {
            const double cap = std::strtod(value.c_str(), nullptr);
            return cap == 0.0 || cap >= 0.5 ? std::string() : "a cap under 0.5 Mbit/s leaves no room for video (0: none)";
          },
          "0 or >= 0.5"));
  app.add_option("--media-start-mbit", o.media_start_mbit, "the media path's rate before the first reports, Mbit/s")
      ->capture_default_str()->check(CLI::Range(0.5, 100000.0));
  app.add_option("--size", o.size, "camera image size WxH (synthetic cameras; the calibration is scaled)")
      ->capture_default_str();
  app.add_option("--fps", o.fps, "camera frame rate, Hz")->capture_default_str()->check(CLI::Range(0.1, 1000.0));
  app.add_option("--quality", o.quality, "JPEG quality")->capture_default_str()->check(CLI::Range(1, 100));
  app.add_option("--codec", o.codec,
                 "video codec: mjpeg (every image a JPEG; the UDP media path), h264 or hevc (each image predicted "
                 "from the last, a fraction of the bytes; on the media path at its rate up to --video-mbit)")
      ->capture_default_str()->check(CLI::IsMember({"mjpeg", "h264", "hevc"}));
  app.add_option("--video-mbit", o.video_mbit, "--codec h264|hevc: the encoders' target rate, both cameras together, Mbit/s")
      ->capture_default_str()->check(CLI::Range(0.1, 10000.0));
  app.add_option("--key-frame-interval", o.key_frame_interval,
                 "--codec h264|hevc: pairs between key frames (a lost frame is repaired sooner: the operator asks for one)")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  app.add_flag("--video-gpu", o.video_gpu,
               "--codec h264|hevc: NVENC first where the machine has an NVIDIA GPU and driver (else the CPU encoder, "
               "with the reason in the log)");
  app.add_option("--subsampling", o.subsampling, "JPEG chroma subsampling")
      ->capture_default_str()->check(CLI::IsMember({"420", "422", "444"}));
  app.add_option("--duration", o.duration_s, "stop after this many seconds (0: run until SIGINT)")
      ->capture_default_str();
  app.add_option("--stats-period", o.stats_period_s, "seconds between statistics lines (0: none)")
      ->capture_default_str();
  app.add_option("--camera-left", o.camera_left, "Aravis device id (name or serial) of the left camera");
  app.add_option("--camera-right", o.camera_right, "Aravis device id of the right camera");
  app.add_option("--auto-nominal", o.auto_nominal,
                 "take the first head pose as the nominal pose (else the console captures it)")
      ->capture_default_str();
  app.add_option("--sphere-radius", o.sphere_radius, "initial sphere radius r, m")->capture_default_str();
  app.add_option("--depth-proxy", o.depth_proxy,
                 "the session's scene proxy from the start: fixed (the sphere of --sphere-radius), radius or grid "
                 "(from the XR app's stereo depth); the XR app follows it (default: none chosen, each XR app "
                 "keeps its own --depth-proxy until the console or the operator chooses)")
      ->check(CLI::IsMember({"fixed", "radius", "grid"}));
  app.add_option("--render-threads", o.render_threads, "threads per synthetic camera")->capture_default_str();
  app.add_option("--preview-width", o.preview_width, "width of the console's camera preview, px")
      ->capture_default_str()->check(CLI::Range(16, 1920));
  app.add_option("--preview-rate", o.preview_hz, "console preview frames per second (0: none)")
      ->capture_default_str()->check(CLI::Range(0.0, 30.0));
  app.add_option("--exposure-ms", o.exposure_ms, "synthetic cameras: exposure, ms (half of it delays delivery)")
      ->capture_default_str()->check(CLI::Range(0.01, 1000.0));
  app.add_option("--transfer-ms", o.transfer_ms, "synthetic cameras: readout and transfer after the exposure, ms")
      ->capture_default_str()->check(CLI::Range(0.0, 1000.0));
  app.add_option("--sim-truth,--true-calib", o.true_calib_path,
                 "synthetic cameras and simulated arm: the calibration they really have (default: "
                 "--calib); a different one shows what a calibration error does to the operator's "
                 "view, and is what the calibration wizards must recover");
  app.add_option("--still-timeout-ms", o.still_timeout_ms,
                 "calibration stills: how long to wait for a pair captured after the request (slow cameras "
                 "or a slow simulation need more)")
      ->capture_default_str()->check(CLI::Range(100, 60000));
  app.add_option("--truth-out", o.truth_path,
                 "synthetic cameras: write each sent frame's true camera poses (CSV) to this file");
  app.add_flag("--sim-manipulator", o.sim_manipulator,
               "synthetic cameras: the wrist marker rides on a simulated manipulator (xArm 6) moving along a "
               "teach-mode path, mounted at --sim-truth's T_robot_mount with the marker at its T_wrist_marker "
               "(both or neither; default: across the table, ManipulatorMounting::example)");
  app.add_option("--arm", o.arm, "head arm: sim (the simulated xArm 6) or xarm (a real xArm 6, robot/arm/xarm/README.md)")
      ->capture_default_str()->check(CLI::IsMember({"sim", "xarm"}));
  app.add_option("--arm-address", o.arm_address, "--arm xarm: the controller's IPv4 address");
  app.add_option("--arm-command-port", o.arm_command_port, "--arm xarm: the controller's command port")
      ->capture_default_str()->check(CLI::Range(1, 65535));
  app.add_option("--arm-report-port", o.arm_report_port, "--arm xarm: the controller's real-time report port")
      ->capture_default_str()->check(CLI::Range(1, 65535));
  app.add_option("--arm-normal-report-port", o.arm_normal_report_port,
                 "--arm xarm: the controller's normal report port (the payload and sensitivity it uses)")
      ->capture_default_str()->check(CLI::Range(1, 65535));
  app.add_option("--arm-payload-kg", o.arm_payload_kg,
                 "--arm xarm: the head's mass on the flange, kg (cameras, lenses, mount); set at start-up and "
                 "read back: a wrong mass shows as collision faults (C31) later")
      ->check(CLI::Range(0.0, 5.0));
  app.add_option("--arm-payload-com-mm", o.arm_payload_com_mm,
                 "--arm xarm: the head's centre of mass in the tool frame, three numbers x y z, mm")
      ->expected(3);
  app.add_option("--arm-collision-sensitivity", o.arm_collision_sensitivity,
                 "--arm xarm: collision sensitivity 0 (off) … 5 (most sensitive), set and read back")
      ->check(CLI::Range(0, 5));
  app.add_flag("--arm-clear-errors", o.arm_clear_errors,
               "--arm xarm: clear the controller's errors and warnings at start-up (check the arm first); "
               "without it, a controller error stops the start with its code and meaning");
  app.add_option("--record", o.record_path,
                 "record the session (stereo frames, state, telemetry, head targets, control) to this MCAP file");
  app.add_option("--record-dir", o.record_dir,
                 "folder for the recordings the console starts (record button, study trials); none: refused");
  app.add_option("--record-compression", o.record_compression, "--record: chunk compression (none, lz4, zstd)")
      ->capture_default_str()->check(CLI::IsMember({"none", "lz4", "zstd"}));
  app.add_option("--replay", o.replay_path,
                 "serve a recorded session (MCAP, --record) on the link at its recorded pace instead of a robot");
  app.add_option("--rate", o.replay_rate, "--replay: pace relative to the recording (2: twice as fast)")
      ->capture_default_str()->check(CLI::Range(0.01, 100.0));
  app.add_flag("--loop", o.replay_loop, "--replay: start again at the end, until stopped");
}

bool checkRobotOptions(RobotOptions& o, std::string* error) {
  auto credentials = linkCredentialsFrom(o.security, {link::trust::LinkRole::kRobot}, error);
  if (!credentials) return false;
  o.credentials = std::move(*credentials);
  if (o.replay() && (o.realArm() || !o.camera_left.empty() || o.sim_manipulator || !o.truth_path.empty() ||
                     !o.true_calib_path.empty())) {
    *error = "--replay serves a recording: no arm, cameras, manipulator or truth options with it";
    return false;
  }
  if (!o.replay() && (o.replay_rate != 1.0 || o.replay_loop)) {
    *error = "--rate and --loop are for --replay";
    return false;
  }
  if (o.realArm()) {
    if (o.arm_address.empty()) {
      *error = "--arm xarm needs --arm-address IP (the controller's address)";
      return false;
    }
    if (o.sim) {
      *error = "--sim means the simulated arm; drop it with --arm xarm";
      return false;
    }
    if (!o.true_calib_path.empty() || !o.truth_path.empty() || o.sim_manipulator) {
      *error = "--sim-truth, --truth-out and --sim-manipulator need the simulated arm (--arm sim)";
      return false;
    }
  } else if (!o.arm_address.empty() || o.arm_clear_errors || o.arm_payload_kg >= 0 || o.arm_collision_sensitivity >= 0 ||
             !o.arm_payload_com_mm.empty()) {
    *error = "--arm-address, --arm-clear-errors, --arm-payload-kg, --arm-payload-com-mm and "
             "--arm-collision-sensitivity are for --arm xarm";
    return false;
  }
  if (!o.camera_left.empty() && (!o.true_calib_path.empty() || !o.truth_path.empty() || o.sim_manipulator)) {
    *error = "--sim-truth, --truth-out and --sim-manipulator need the synthetic cameras";
    return false;
  }
  if (o.sim && !o.camera_left.empty()) {
    *error = "--sim uses synthetic cameras; drop --camera-left/--camera-right";
    return false;
  }
  if (o.camera_left.empty() != o.camera_right.empty()) {
    *error = "give both --camera-left and --camera-right, or neither (--sim)";
    return false;
  }
  if (std::sscanf(o.size.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width <= 0 || o.height <= 0 ||
      o.width > 16384 || o.height > 16384) {
    *error = "--size '" + o.size + "' is not WxH";
    return false;
  }
  return true;
}

}  // namespace telesphere::app
