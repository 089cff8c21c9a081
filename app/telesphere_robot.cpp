// SPDX-License-Identifier: MIT
/// @brief telesphere-robot: the robot side (DESIGN.md §1, §4, §5). Owns the cameras, the head arm
///        and the link server:
///          cameras → stereo pairing → parallel JPEG encode → link (frames, with T_robot_cam at
///          capture time from the joint-state buffer)
///          link (head targets) → head controller → arm → joint-state buffer → link (state)
///
/// With --sim (the default; the only arm this build can drive) the arm is the simulated xArm 6
/// and the cameras are synthetic, rendering the default scene through the true calibration
/// (--sim-truth, by default the one the robot uses) at the arm's true pose at the middle of each
/// exposure, delivered after exposure/2 + transfer; frames are stamped, as on the real robot,
/// with the pose the joint-state buffer interpolates. --truth-out writes that truth per frame.
/// --sim-manipulator adds the manipulator carrying the wrist marker (hand-eye calibration): a
/// simulated xArm 6 at the true T_robot_mount moving along a teach-mode path, its joints reported
/// at 100 Hz and carried in calibration stills. With --camera-left/--camera-right the cameras are GenICam cameras through Aravis.
/// Stops cleanly on SIGINT/SIGTERM or after --duration seconds; prints statistics periodically.
/// Exit codes: 0 ok, 1 bad arguments or files, 2 a camera or the link could not start.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "robot/aravis_camera.h"
#include "robot/calibration_in_use.h"
#include "robot/ground_truth_log.h"
#include "robot/head_arm_sim.h"
#include "robot/head_loop.h"
#include "robot/preview_streamer.h"
#include "robot/robot_control.h"
#include "robot/robot_health_reporter.h"
#include "robot/simulated_manipulator.h"
#include "robot/synthetic_camera.h"
#include "robot/synthetic_scene.h"
#include "robot/video_streamer.h"

namespace {

using namespace telesphere;

std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop = true; }

bool parseSize(const std::string& text, int& width, int& height) {
  return std::sscanf(text.c_str(), "%dx%d", &width, &height) == 2 && width > 0 && height > 0 &&
         width <= 16384 && height <= 16384;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"telesphere-robot: cameras, head arm and link server of the robot side"};
  std::string calib_path = TELESPHERE_SOURCE_DIR "/calib/data/sim_calibration.yaml";
  int port = 5760;
  std::string size = "640x360";  // the synthetic cameras render in real time at this size
  int still_timeout_ms = 800;
  double fps = 45.0;
  int quality = 90;
  std::string subsampling = "420";
  double duration_s = 0.0;
  double stats_period_s = 2.0;
  std::string camera_left, camera_right;
  bool auto_nominal = true;
  double sphere_radius = 1.0;
  int render_threads = 2;
  int preview_width = 320;
  double preview_hz = 5.0;
  bool sim = false;  // the default anyway; explicit for scripts
  double exposure_ms = 8.0;   // the paper's cameras
  double transfer_ms = 10.0;  // the paper: about 10 ms over USB
  std::string true_calib_path;
  std::string truth_path;
  bool sim_manipulator = false;
  app.add_flag("--sim", sim, "simulated arm and synthetic cameras (the default)");
  app.add_option("--calib", calib_path, "system calibration (YAML, kalibr camchain or Basalt JSON)")
      ->capture_default_str();
  app.add_option("--port", port, "link base port (frames, state, uplink, control: port..port+3)")
      ->capture_default_str()->check(CLI::Range(1024, 65532));
  app.add_option("--size", size, "camera image size WxH (synthetic cameras; the calibration is scaled)")
      ->capture_default_str();
  app.add_option("--fps", fps, "camera frame rate, Hz")->capture_default_str()->check(CLI::Range(0.1, 1000.0));
  app.add_option("--quality", quality, "JPEG quality")->capture_default_str()->check(CLI::Range(1, 100));
  app.add_option("--subsampling", subsampling, "JPEG chroma subsampling")
      ->capture_default_str()->check(CLI::IsMember({"420", "422", "444"}));
  app.add_option("--duration", duration_s, "stop after this many seconds (0: run until SIGINT)")
      ->capture_default_str();
  app.add_option("--stats-period", stats_period_s, "seconds between statistics lines (0: none)")
      ->capture_default_str();
  app.add_option("--camera-left", camera_left, "Aravis device id (name or serial) of the left camera");
  app.add_option("--camera-right", camera_right, "Aravis device id of the right camera");
  app.add_option("--auto-nominal", auto_nominal,
                 "take the first head pose as the nominal pose (else the console captures it)")
      ->capture_default_str();
  app.add_option("--sphere-radius", sphere_radius, "initial sphere radius r, m")->capture_default_str();
  app.add_option("--render-threads", render_threads, "threads per synthetic camera")->capture_default_str();
  app.add_option("--preview-width", preview_width, "width of the console's camera preview, px")
      ->capture_default_str()->check(CLI::Range(16, 1920));
  app.add_option("--preview-rate", preview_hz, "console preview frames per second (0: none)")
      ->capture_default_str()->check(CLI::Range(0.0, 30.0));
  app.add_option("--exposure-ms", exposure_ms, "synthetic cameras: exposure, ms (half of it delays delivery)")
      ->capture_default_str()->check(CLI::Range(0.01, 1000.0));
  app.add_option("--transfer-ms", transfer_ms, "synthetic cameras: readout and transfer after the exposure, ms")
      ->capture_default_str()->check(CLI::Range(0.0, 1000.0));
  app.add_option("--sim-truth,--true-calib", true_calib_path,
                 "synthetic cameras and simulated arm: the calibration they really have (default: "
                 "--calib); a different one shows what a calibration error does to the operator's "
                 "view, and is what the calibration wizards must recover");
  app.add_option("--still-timeout-ms", still_timeout_ms,
                 "calibration stills: how long to wait for a pair captured after the request (slow cameras "
                 "or a slow simulation need more)")
      ->capture_default_str()->check(CLI::Range(100, 60000));
  app.add_option("--truth-out", truth_path,
                 "synthetic cameras: write each sent frame's true camera poses (CSV) to this file");
  app.add_flag("--sim-manipulator", sim_manipulator,
               "synthetic cameras: the wrist marker rides on a simulated manipulator (xArm 6) moving along a "
               "teach-mode path, mounted at --sim-truth's T_robot_mount with the marker at its T_wrist_marker "
               "(both or neither; default: across the table, ManipulatorMounting::example)");
  CLI11_PARSE(app, argc, argv);

  auto loaded = calib::loadCalibrationFile(calib_path);
  if (!loaded) {
    std::cerr << "telesphere-robot: " << loaded.error().describe() << '\n';
    return 1;
  }
  const calib::SystemCalibration& calibration = *loaded;
  if (calibration.cameras.size() != 2 || !calibration.T_cam_l_cam_r || !calibration.T_flange_cam_l) {
    std::cerr << "telesphere-robot: " << calib_path
              << ": needs two cameras, T_cam_l_cam_r and T_flange_cam_l (run telesphere-calib "
                 "intrinsics and handeye first)\n";
    return 1;
  }
  if (!camera_left.empty() && (!true_calib_path.empty() || !truth_path.empty() || sim_manipulator)) {
    std::cerr << "telesphere-robot: --sim-truth, --truth-out and --sim-manipulator need the synthetic cameras\n";
    return 1;
  }
  calib::SystemCalibration true_calibration = calibration;
  if (!true_calib_path.empty()) {
    auto loaded_true = calib::loadCalibrationFile(true_calib_path);
    if (!loaded_true) {
      std::cerr << "telesphere-robot: --sim-truth: " << loaded_true.error().describe() << '\n';
      return 1;
    }
    true_calibration = *loaded_true;
    if (true_calibration.cameras.size() != 2 || !true_calibration.T_cam_l_cam_r || !true_calibration.T_flange_cam_l) {
      std::cerr << "telesphere-robot: --sim-truth " << true_calib_path
                << ": needs two cameras, T_cam_l_cam_r and T_flange_cam_l\n";
      return 1;
    }
  }
  // The manipulator with the wrist marker, reporting its joints like the head arm.
  std::optional<robot::SimulatedManipulator> manipulator;
  robot::JointStateBuffer manipulator_reports{robot::HeadGeometry{}};
  if (sim_manipulator) {
    robot::SimulatedManipulatorConfig manipulator_config;
    if (true_calibration.T_robot_mount.has_value() != true_calibration.T_wrist_marker.has_value()) {
      std::cerr << "telesphere-robot: --sim-manipulator: the true calibration has only one of T_robot_mount and "
                   "T_wrist_marker (give both or neither)\n";
      return 1;
    }
    if (true_calibration.T_robot_mount) {
      manipulator_config.mounting = {*true_calibration.T_robot_mount, *true_calibration.T_wrist_marker};
    }
    std::string error;
    manipulator = robot::SimulatedManipulator::create(manipulator_config, &error);
    if (!manipulator) {
      std::cerr << "telesphere-robot: --sim-manipulator: " << error << '\n';
      return 1;
    }
  }
  if (sim && !camera_left.empty()) {
    std::cerr << "telesphere-robot: --sim uses synthetic cameras; drop --camera-left/--camera-right\n";
    return 1;
  }
  if (camera_left.empty() != camera_right.empty()) {
    std::cerr << "telesphere-robot: give both --camera-left and --camera-right, or neither (--sim)\n";
    return 1;
  }
  int width = 0, height = 0;
  if (!parseSize(size, width, height)) {
    std::cerr << "telesphere-robot: --size '" << size << "' is not WxH\n";
    return 1;
  }
  robot::JpegSettings jpeg;
  jpeg.quality = quality;
  jpeg.subsampling = subsampling == "444"   ? robot::ChromaSubsampling::k444
                     : subsampling == "422" ? robot::ChromaSubsampling::k422
                                            : robot::ChromaSubsampling::k420;

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);

  // The head loop: simulated arm (no xArm driver in this build), controller, joint-state buffer.
  robot::SteadyClock clock;
  robot::HeadControllerConfig controller_config;
  controller_config.geometry.T_flange_cam_l = *calibration.T_flange_cam_l;
  controller_config.geometry.T_cam_l_cam_r = *calibration.T_cam_l_cam_r;
  robot::HeadController controller(controller_config);
  robot::SimulatedArmConfig arm_config;
  {  // start at the nominal head pose so the first frames already look where the operator will
    const auto ik = controller.kinematics().inverse(
        controller_config.T_robot_nom * controller_config.geometry.T_flange_head().inverse(),
        robot::JointVector::Zero(), controller_config.ik);
    if (ik.status == robot::IkResult::Status::kConverged) arm_config.q_initial = ik.q;
  }
  // Ground truth of the simulation: the arm's noise-free joints at every physics step (1 ms),
  // through the true calibration.
  robot::HeadGeometry true_geometry;
  true_geometry.T_flange_cam_l = *true_calibration.T_flange_cam_l;
  true_geometry.T_cam_l_cam_r = *true_calibration.T_cam_l_cam_r;
  robot::JointStateBufferConfig truth_config;
  truth_config.capacity = 8192;  // 8 s at 1 kHz
  robot::JointStateBuffer truth(true_geometry, truth_config);
  arm_config.on_true_state = [&truth](const robot::JointState& s) { truth.push(s); };
  robot::SimulatedArm arm(clock, arm_config);
  robot::JointStateBuffer joints(controller_config.geometry);

  link::LinkEndpoints endpoints;
  endpoints.base_port = port;
  std::unique_ptr<link::LinkServer> server;
  try {
    server = std::make_unique<link::LinkServer>(endpoints);
  } catch (const std::exception& e) {
    std::cerr << "telesphere-robot: cannot open the link on ports " << port << ".." << port + 3
              << ": " << e.what() << '\n';
    return 2;
  }
  // The calibration in use, applied and reverted live by the console (link apply_calibration).
  robot::CalibrationInUse calibration_in_use(calibration, "--calib " + calib_path, clock);
  robot::TelemetryBatcher telemetry;
  robot::HeadLoopConfig loop_config;
  loop_config.calibration = &calibration_in_use;
  loop_config.auto_nominal = auto_nominal;
  loop_config.sphere_radius = sphere_radius;
  loop_config.telemetry = &telemetry;
  robot::HeadLoop loop(arm, controller, joints, *server, clock, loop_config);

  // Camera poses at capture time through the calibration in use; before any joint state, the
  // pose at the initial configuration.
  const robot::StereoPosesAt poses = [&calibration_in_use, &joints, q0 = arm_config.q_initial](
                                         std::int64_t left_ns, std::int64_t right_ns) {
    return calibration_in_use.posesAt(joints, q0, left_ns, right_ns);
  };
  const Eigen::Isometry3d T_robot_flange0 = controller.kinematics().forward(arm_config.q_initial);
  const Eigen::Isometry3d T_robot_cam_l0 = T_robot_flange0 * *true_calibration.T_flange_cam_l;
  const Eigen::Isometry3d T_robot_cam_r0 = T_robot_cam_l0 * *true_calibration.T_cam_l_cam_r;
  // Where a synthetic camera really is at t_ns. The frame is rendered after its readout, by when
  // the head loop (100 Hz) has normally simulated past t_ns; if it lags (a loaded machine), the
  // render waits for it, up to 2 s: a frame drawn at a made-up pose would put a silent error
  // into everything downstream (calibration stills above all). Only before the arm's first state
  // is the initial configuration's pose the truth; any other fallback is counted and said.
  std::atomic<std::uint64_t> truth_fallbacks{0};  // the cameras stop before main returns
  const auto true_pose = [&truth, &clock, &truth_fallbacks](robot::CameraSide side, std::int64_t t_ns,
                                                            const Eigen::Isometry3d& T0) {
    for (int waited_ms = 0; waited_ms < 2000; ++waited_ms) {
      const auto window = truth.window();
      if (window && window->second >= t_ns) break;
      if (!window && clock.nowNs() < t_ns) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (const auto T = truth.T_robot_cam(side, t_ns)) return *T;
    if (truth.window() && truth_fallbacks.fetch_add(1) % 100 == 0)
      std::cerr << "telesphere-robot: synthetic camera: no true arm pose at the capture time after 2 s (the head "
                   "loop is stalled); the frame shows the initial pose (" << truth_fallbacks.load() << " so far)\n";
    return T0;
  };

  std::unique_ptr<robot::CameraSource> left, right;
  if (camera_left.empty()) {
    robot::DefaultSceneLayout layout;
    if (manipulator) layout.marker_pose = [&manipulator](std::int64_t t_ns) { return manipulator->T_robot_marker(t_ns); };
    auto scene = std::make_shared<const robot::SyntheticScene>(robot::defaultScene(layout));
    const auto make = [&](int index, robot::CameraSide side, const Eigen::Isometry3d& T0,
                          const char* name) -> std::unique_ptr<robot::CameraSource> {
      std::string error;
      const auto camera = calib::atResolution(true_calibration.cameras[index], width, height, &error);
      if (!camera) {
        std::cerr << "telesphere-robot: " << error << '\n';
        return nullptr;
      }
      robot::SyntheticCameraOptions options;
      options.name = name;
      options.fps = fps;
      options.threads = render_threads;
      options.exposure_us = static_cast<std::uint32_t>(std::lround(exposure_ms * 1000.0));
      options.transfer_ns = std::llround(transfer_ms * 1e6);
      return std::make_unique<robot::SyntheticCamera>(
          camera->camera, width, height, scene,
          [true_pose, side, T0](std::int64_t t_ns) { return true_pose(side, t_ns, T0); }, clock, options);
    };
    left = make(0, robot::CameraSide::kLeft, T_robot_cam_l0, "synthetic-left");
    right = make(1, robot::CameraSide::kRight, T_robot_cam_r0, "synthetic-right");
    if (!left || !right) return 1;
  } else {
    for (auto [id, out] : {std::pair{&camera_left, &left}, std::pair{&camera_right, &right}}) {
      robot::AravisCameraOptions options;
      options.device_id = *id;
      options.frame_rate_hz = fps;
      *out = std::make_unique<robot::AravisCamera>(options);
    }
  }
  for (robot::CameraSource* camera : {left.get(), right.get()}) {
    std::string error;
    if (!camera->start(&error)) {
      std::cerr << "telesphere-robot: camera " << camera->name() << ": " << error << '\n';
      return 2;
    }
  }

  robot::StereoPairerOptions pairing;
  pairing.tolerance_ns = static_cast<std::int64_t>(0.25e9 / fps);  // a quarter period
  robot::StereoPairSource pairs(*left, *right, pairing);
  robot::PreviewOptions preview_options;
  preview_options.max_width = preview_width;
  preview_options.rate_hz = preview_hz > 0 ? preview_hz : 1.0;
  robot::PreviewStreamer preview(*server, preview_options);
  robot::VideoStreamerConfig video_config;
  video_config.jpeg = jpeg;
  video_config.telemetry = &telemetry;
  std::unique_ptr<robot::GroundTruthLog> truth_log;
  if (!truth_path.empty()) {
    std::string error;
    truth_log = robot::GroundTruthLog::open(truth_path, truth, &error);
    if (!truth_log) {
      std::cerr << "telesphere-robot: " << error << '\n';
      return 1;
    }
  }
  robot::StereoStillTaker stills(joints, clock, manipulator ? &manipulator_reports : nullptr);
  video_config.on_sent = [&preview, &truth_log, &loop, &stills, preview_hz](const robot::StereoFrame& pair,
                                                                            std::uint64_t sequence) {
    stills.offer(pair, sequence);
    if (preview_hz > 0) preview.offer(pair, sequence);
    if (truth_log) truth_log->frameSent(pair, sequence, loop.nominalMapping());
  };
  robot::VideoStreamer video(pairs, *server, clock, poses, video_config);

  robot::RobotControl control(loop, &video, &stills, std::chrono::milliseconds(still_timeout_ms), &calibration_in_use);
  server->setControlHandler([&control](const link::proto::ControlRequest& r) { return control.handle(r); });
  robot::RobotHealthSources health_sources;
  health_sources.cameras = {left.get(), right.get()};
  health_sources.pairs = &pairs;
  health_sources.video = &video;
  health_sources.loop = &loop;
  health_sources.control = &control;
  health_sources.server = server.get();
  health_sources.telemetry = &telemetry;
  health_sources.arm = "simulated xArm 6";
  health_sources.cameras_kind = camera_left.empty() ? "synthetic" : "aravis";
  robot::RobotHealthReporter health(health_sources, clock);

  std::thread head_thread([&] { loop.run(g_stop); });
  std::thread manipulator_thread([&] {  // the manipulator's 100 Hz reports
    while (manipulator && !g_stop) {
      manipulator->update(clock.nowNs(), manipulator_reports);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  if (preview_hz > 0) preview.start();
  pairs.start();
  video.start();
  std::cerr << "telesphere-robot: " << (camera_left.empty() ? "simulated arm, synthetic cameras " : "cameras ")
            << width << "x" << height << " at " << fps << " Hz, link on port " << port << '\n';

  const auto t0 = std::chrono::steady_clock::now();
  auto next_stats = t0 + std::chrono::duration<double>(stats_period_s);
  constexpr auto kHealthPeriod = std::chrono::milliseconds(500);
  auto next_health = t0;
  std::uint64_t frames_before = 0;
  while (!g_stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto now = std::chrono::steady_clock::now();
    if (duration_s > 0 && now - t0 >= std::chrono::duration<double>(duration_s)) g_stop = true;
    if (now >= next_health) {
      server->publishHealth(health.make());
      next_health = now + kHealthPeriod;
    }
    if (stats_period_s > 0 && now >= next_stats) {
      const auto v = video.stats();
      const auto p = pairs.stats();
      std::fprintf(stderr,
                   "telesphere-robot: %.1f fps sent, encode %.1f ms, capture->sent %.1f ms, pairs "
                   "dropped %llu, poses from joints %llu / fixed %llu, head targets sent %lld\n",
                   double(v.frames_sent - frames_before) / stats_period_s, v.encode_ms_last,
                   double(v.capture_to_sent_ns_last) * 1e-6,
                   static_cast<unsigned long long>(p.dropped[0].total() + p.dropped[1].total()),
                   static_cast<unsigned long long>(v.poses_from_joints),
                   static_cast<unsigned long long>(v.poses_fixed),
                   static_cast<long long>(loop.targetsSent()));
      frames_before = v.frames_sent;
      next_stats += std::chrono::duration<double>(stats_period_s);
    }
  }
  video.stop();
  preview.stop();
  pairs.stop();
  left->stop();
  right->stop();
  head_thread.join();
  manipulator_thread.join();
  server->setControlHandler(nullptr);  // the link's thread must not call into what goes next
  const auto v = video.stats();
  std::fprintf(stderr, "telesphere-robot: stopped after %llu frames\n",
               static_cast<unsigned long long>(v.frames_sent));
  return 0;
}
