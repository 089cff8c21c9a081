// SPDX-License-Identifier: MIT
#include "app/robot_assembly.h"

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

/// In construction order; destroyed in reverse (each part outlives the parts that use it).
struct RobotAssembly::Parts {
  RobotOptions options;
  robot::SteadyClock clock;
  calib::SystemCalibration calibration, true_calibration;
  std::optional<robot::SimulatedManipulator> manipulator;  ///< carries the wrist marker (hand-eye)
  robot::JointStateBuffer manipulator_reports{robot::HeadGeometry{}};
  std::unique_ptr<robot::HeadController> controller;
  robot::JointVector q_initial = robot::JointVector::Zero();
  /// The simulated arm's noise-free joints at every physics step (null with a real arm).
  std::unique_ptr<robot::JointStateBuffer> truth;
  std::unique_ptr<robot::HeadArm> arm;  ///< SimulatedArm or XArmHeadArm
  std::string arm_description;          ///< for the console's health view
  std::unique_ptr<robot::JointStateBuffer> joints;  ///< the arm's reports, with the calibration in use
  std::unique_ptr<link::LinkServer> server;
  std::unique_ptr<robot::RecordingSwitch> recording;  ///< --record, --record-dir, the console's requests
  std::unique_ptr<robot::CalibrationInUse> calibration_in_use;
  robot::TelemetryBatcher telemetry;
  std::unique_ptr<robot::HeadLoop> loop;
  std::unique_ptr<robot::TrueCameraPoses> true_poses;
  std::unique_ptr<robot::CameraSource> left, right;
  std::unique_ptr<robot::StereoPairSource> pairs;
  std::unique_ptr<robot::PreviewStreamer> preview;
  std::unique_ptr<robot::GroundTruthLog> truth_log;
  std::unique_ptr<robot::StereoStillTaker> stills;
  std::unique_ptr<robot::VideoStreamer> video;
  std::unique_ptr<robot::RobotControl> control;
  std::unique_ptr<robot::RobotHealthReporter> health;
};

namespace {

bool hasStereoMount(const calib::SystemCalibration& c) {
  return c.cameras.size() == 2 && c.T_cam_l_cam_r && c.T_flange_cam_l;
}

/// Loads and checks the calibration in use and the true one (the simulation's); false with the reason.
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

/// The manipulator with the wrist marker, at the true calibration's mounting when it has one.
bool makeManipulator(RobotAssembly::Parts& p, std::string* error) {
  const calib::SystemCalibration& truth = p.true_calibration;
  if (truth.T_robot_mount.has_value() != truth.T_wrist_marker.has_value()) {
    *error = "--sim-manipulator: the true calibration has only one of T_robot_mount and T_wrist_marker (give "
             "both or neither)";
    return false;
  }
  robot::SimulatedManipulatorConfig config;
  if (truth.T_robot_mount) config.mounting = {*truth.T_robot_mount, *truth.T_wrist_marker};
  p.manipulator = robot::SimulatedManipulator::create(config, error);
  if (!p.manipulator) *error = "--sim-manipulator: " + *error;
  return p.manipulator.has_value();
}

/// The head loop: the arm (simulated, or the real xArm started and at the nominal joints),
/// controller, joint-state buffers (reported, and with the simulated arm the truth). False with
/// the reason and *exit_code (2: the real arm could not start).
bool makeHead(RobotAssembly::Parts& p, int* exit_code, std::string* error) {
  robot::HeadControllerConfig controller_config;
  controller_config.geometry.T_flange_cam_l = *p.calibration.T_flange_cam_l;
  controller_config.geometry.T_cam_l_cam_r = *p.calibration.T_cam_l_cam_r;
  p.controller = std::make_unique<robot::HeadController>(controller_config);
  // Start at the nominal head pose so the first frames already look where the operator will.
  const auto ik = p.controller->kinematics().inverse(
      controller_config.T_robot_nom * controller_config.geometry.T_flange_head().inverse(),
      robot::JointVector::Zero(), controller_config.ik);
  if (ik.status == robot::IkResult::Status::kConverged) p.q_initial = ik.q;

  p.joints = std::make_unique<robot::JointStateBuffer>(controller_config.geometry);
  const RobotOptions& o = p.options;
  if (o.realArm()) {
    robot::XArmOptions xarm;
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
    auto arm = robot::XArmHeadArm::start(xarm, p.clock, error, [](const std::string& step) {
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
  robot::HeadGeometry true_geometry;
  true_geometry.T_flange_cam_l = *p.true_calibration.T_flange_cam_l;
  true_geometry.T_cam_l_cam_r = *p.true_calibration.T_cam_l_cam_r;
  robot::JointStateBufferConfig truth_config;
  truth_config.capacity = 8192;  // 8 s at 1 kHz
  p.truth = std::make_unique<robot::JointStateBuffer>(true_geometry, truth_config);
  robot::SimulatedArmConfig arm_config;
  arm_config.q_initial = p.q_initial;
  arm_config.on_true_state = [truth = p.truth.get()](const robot::JointState& s) { truth->push(s); };
  p.arm = std::make_unique<robot::SimulatedArm>(p.clock, arm_config);
  p.arm_description = "simulated xArm 6";
  return true;
}

/// Synthetic cameras (rendering at the arm's true pose) or GenICam cameras; started. False with
/// the reason and *exit_code.
bool makeCameras(RobotAssembly::Parts& p, int* exit_code, std::string* error) {
  const RobotOptions& o = p.options;
  if (o.syntheticCameras()) {
    const Eigen::Isometry3d T_robot_cam_l0 =
        p.controller->kinematics().forward(p.q_initial) * *p.true_calibration.T_flange_cam_l;
    // With the real arm there is no truth but what it reports: the synthetic cameras render there.
    p.true_poses = std::make_unique<robot::TrueCameraPoses>(
        p.truth ? *p.truth : *p.joints, p.clock,
        std::array<Eigen::Isometry3d, 2>{T_robot_cam_l0, T_robot_cam_l0 * *p.true_calibration.T_cam_l_cam_r});
    robot::DefaultSceneLayout layout;
    if (p.manipulator)
      layout.marker_pose = [m = &*p.manipulator](std::int64_t t_ns) { return m->T_robot_marker(t_ns); };
    auto scene = std::make_shared<const robot::SyntheticScene>(robot::defaultScene(layout));
    // One trigger line for both: when rendering falls behind the frame rate they still expose the
    // same ticks, so every frame can pair.
    const auto trigger = std::make_shared<robot::SyntheticTrigger>();
    for (int index : {0, 1}) {
      const auto camera = calib::atResolution(p.true_calibration.cameras[std::size_t(index)], o.width, o.height, error);
      if (!camera) {
        *exit_code = 1;
        return false;
      }
      robot::SyntheticCameraOptions options;
      options.name = index == 0 ? "synthetic-left" : "synthetic-right";
      options.fps = o.fps;
      options.threads = o.render_threads;
      options.exposure_us = static_cast<std::uint32_t>(std::lround(o.exposure_ms * 1000.0));
      options.transfer_ns = std::llround(o.transfer_ms * 1e6);
      options.trigger = trigger;
      const robot::CameraSide side = index == 0 ? robot::CameraSide::kLeft : robot::CameraSide::kRight;
      (index == 0 ? p.left : p.right) = std::make_unique<robot::SyntheticCamera>(
          camera->camera, o.width, o.height, scene,
          [poses = p.true_poses.get(), side](std::int64_t t_ns) { return poses->at(side, t_ns); }, p.clock,
          options);
    }
  } else {
    for (auto [id, out] : {std::pair{&o.camera_left, &p.left}, std::pair{&o.camera_right, &p.right}}) {
      robot::AravisCameraOptions options;
      options.device_id = *id;
      options.frame_rate_hz = o.fps;
      *out = std::make_unique<robot::AravisCamera>(options);
    }
  }
  for (robot::CameraSource* camera : {p.left.get(), p.right.get()}) {
    if (!camera->start(error)) {
      *error = "camera " + camera->name() + ": " + *error;
      *exit_code = 2;
      return false;
    }
  }
  return true;
}

}  // namespace

RobotAssembly::RobotAssembly(std::unique_ptr<Parts> parts) : parts_(std::move(parts)) {}
RobotAssembly::~RobotAssembly() = default;

std::unique_ptr<RobotAssembly> RobotAssembly::build(const RobotOptions& options, int* exit_code, std::string* error) {
  auto p = std::make_unique<Parts>();
  p->options = options;
  const RobotOptions& o = p->options;
  *exit_code = 1;
  if (!loadCalibrations(*p, error)) return nullptr;
  if (o.sim_manipulator && !makeManipulator(*p, error)) return nullptr;
  if (!makeHead(*p, exit_code, error)) return nullptr;

  link::LinkEndpoints endpoints;
  endpoints.base_port = o.port;
  try {
    p->server = std::make_unique<link::LinkServer>(endpoints);
  } catch (const std::exception& e) {
    *error = "cannot open the link on ports " + std::to_string(o.port) + ".." + std::to_string(o.port + 3) + ": " +
             e.what();
    *exit_code = 2;
    return nullptr;
  }
  // The calibration in use, applied and reverted live by the console (link apply_calibration).
  p->calibration_in_use = std::make_unique<robot::CalibrationInUse>(p->calibration, "--calib " + o.calib_path, p->clock);
  if (!o.calib_save.empty()) p->calibration_in_use->setSavePath(o.calib_save);
  record::LinkRecorderOptions recording;
  recording.mcap.compression = *record::parseCompression(o.record_compression);
  recording.metadata = {{"arm", p->arm_description}, {"cameras", o.syntheticCameras() ? "synthetic" : "aravis"},
                        {"calibration_file", o.calib_path}};
  p->recording = std::make_unique<robot::RecordingSwitch>(*p->server, o.record_dir, recording);
  p->recording->setCalibrationSource([in_use = p->calibration_in_use.get()] {
    link::proto::CalibrationInUse c;
    in_use->fill(&c);
    return std::optional(c);
  });
  if (!o.record_path.empty() && !p->recording->startFile(o.record_path, error)) {
    *error = "--record: " + *error;
    return nullptr;
  }
  robot::HeadLoopConfig loop_config;
  loop_config.calibration = p->calibration_in_use.get();
  loop_config.auto_nominal = o.auto_nominal;
  loop_config.sphere_radius = o.sphere_radius;
  loop_config.telemetry = &p->telemetry;
  p->loop = std::make_unique<robot::HeadLoop>(*p->arm, *p->controller, *p->joints, *p->server, p->clock, loop_config);

  if (!makeCameras(*p, exit_code, error)) return nullptr;

  robot::StereoPairerOptions pairing;
  pairing.tolerance_ns = static_cast<std::int64_t>(0.25e9 / o.fps);  // a quarter period
  p->pairs = std::make_unique<robot::StereoPairSource>(*p->left, *p->right, pairing);
  robot::PreviewOptions preview_options;
  preview_options.max_width = o.preview_width;
  preview_options.rate_hz = o.preview_hz > 0 ? o.preview_hz : 1.0;
  p->preview = std::make_unique<robot::PreviewStreamer>(*p->server, preview_options);
  if (!o.truth_path.empty() && !(p->truth_log = robot::GroundTruthLog::open(o.truth_path, *p->truth, error))) {
    *exit_code = 1;
    return nullptr;
  }
  p->stills = std::make_unique<robot::StereoStillTaker>(*p->joints, p->clock,
                                                        p->manipulator ? &p->manipulator_reports : nullptr);
  robot::VideoStreamerConfig video_config;
  video_config.jpeg.quality = o.quality;
  video_config.jpeg.subsampling = o.subsampling == "444"   ? robot::ChromaSubsampling::k444
                                  : o.subsampling == "422" ? robot::ChromaSubsampling::k422
                                                           : robot::ChromaSubsampling::k420;
  video_config.telemetry = &p->telemetry;
  video_config.on_sent = [parts = p.get()](const robot::StereoFrame& pair, std::uint64_t sequence) {
    parts->stills->offer(pair, sequence);
    if (parts->options.preview_hz > 0) parts->preview->offer(pair, sequence);
    if (parts->truth_log) parts->truth_log->frameSent(pair, sequence, parts->loop->nominalMapping());
  };
  // Camera poses at capture time through the calibration in use; before any joint state, the
  // pose at the initial configuration.
  const robot::StereoPosesAt poses = [parts = p.get()](std::int64_t left_ns, std::int64_t right_ns) {
    return parts->calibration_in_use->posesAt(*parts->joints, parts->q_initial, left_ns, right_ns);
  };
  p->video = std::make_unique<robot::VideoStreamer>(*p->pairs, *p->server, p->clock, poses, video_config);
  p->control = std::make_unique<robot::RobotControl>(*p->loop, p->video.get(), p->stills.get(),
                                                     std::chrono::milliseconds(o.still_timeout_ms),
                                                     p->calibration_in_use.get(), p->recording.get());
  robot::RobotHealthSources health_sources;
  health_sources.cameras = {p->left.get(), p->right.get()};
  health_sources.pairs = p->pairs.get();
  health_sources.video = p->video.get();
  health_sources.loop = p->loop.get();
  health_sources.control = p->control.get();
  health_sources.server = p->server.get();
  health_sources.telemetry = &p->telemetry;
  health_sources.recording = p->recording.get();
  health_sources.arm = p->arm_description;
  health_sources.xarm = dynamic_cast<const robot::XArmHeadArm*>(p->arm.get());
  health_sources.cameras_kind = o.syntheticCameras() ? "synthetic" : "aravis";
  p->health = std::make_unique<robot::RobotHealthReporter>(health_sources, p->clock);
  *exit_code = 0;
  return std::unique_ptr<RobotAssembly>(new RobotAssembly(std::move(p)));
}

std::string RobotAssembly::describe() const {
  const RobotOptions& o = parts_->options;
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", o.fps);
  return (o.realArm() ? "xArm 6 at " + o.arm_address : std::string("simulated arm")) +
         (o.syntheticCameras() ? ", synthetic cameras " : ", cameras ") +
         std::to_string(o.width) + "x" + std::to_string(o.height) + " at " + rate + " Hz, link on port " +
         std::to_string(o.port);
}

std::uint64_t RobotAssembly::run(std::atomic<bool>& stop) {
  Parts& p = *parts_;
  const RobotOptions& o = p.options;
  p.server->setControlHandler([&p](const link::proto::ControlRequest& r) { return p.control->handle(r); });
  std::thread head_thread([&] { p.loop->run(stop); });
  std::thread manipulator_thread([&] {  // the manipulator's 100 Hz reports
    while (p.manipulator && !stop) {
      p.manipulator->update(p.clock.nowNs(), p.manipulator_reports);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  if (o.preview_hz > 0) p.preview->start();
  p.pairs->start();
  p.video->start();

  const auto t0 = std::chrono::steady_clock::now();
  auto next_stats = t0 + std::chrono::duration<double>(o.stats_period_s);
  constexpr auto kHealthPeriod = std::chrono::milliseconds(500);
  auto next_health = t0;
  std::uint64_t frames_before = 0;
  while (!stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto now = std::chrono::steady_clock::now();
    if (o.duration_s > 0 && now - t0 >= std::chrono::duration<double>(o.duration_s)) stop = true;
    if (now >= next_health) {
      p.server->publishHealth(p.health->make());
      next_health = now + kHealthPeriod;
    }
    if (o.stats_period_s > 0 && now >= next_stats) {
      const auto v = p.video->stats();
      const auto pairs = p.pairs->stats();
      std::fprintf(stderr,
                   "telesphere-robot: %.1f fps sent, encode %.1f ms, capture->sent %.1f ms, pairs "
                   "dropped %llu, poses from joints %llu / fixed %llu, head targets sent %lld\n",
                   double(v.frames_sent - frames_before) / o.stats_period_s, v.encode_ms_last,
                   double(v.capture_to_sent_ns_last) * 1e-6,
                   static_cast<unsigned long long>(pairs.dropped[0].total() + pairs.dropped[1].total()),
                   static_cast<unsigned long long>(v.poses_from_joints), static_cast<unsigned long long>(v.poses_fixed),
                   static_cast<long long>(p.loop->targetsSent()));
      frames_before = v.frames_sent;
      next_stats += std::chrono::duration<double>(o.stats_period_s);
    }
  }
  p.video->stop();
  p.preview->stop();
  p.pairs->stop();
  p.left->stop();
  p.right->stop();
  head_thread.join();
  manipulator_thread.join();
  p.server->setControlHandler(nullptr);  // the link's thread must not call into what goes next
  if (p.recording->active()) {
    std::string why;
    const bool whole = p.recording->stop(&why) && p.recording->waitFinished(&why);
    const auto r = p.recording->state();
    std::fprintf(stderr, "telesphere-robot: recorded %llu messages (%.1f MB) to %s%s%s\n",
                 static_cast<unsigned long long>(r.messages()), double(r.bytes()) * 1e-6, r.file().c_str(),
                 whole ? "" : ": ", whole ? "" : why.c_str());
  }
  return p.video->stats().frames_sent;
}

}  // namespace telesphere::app
