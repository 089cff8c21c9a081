// SPDX-License-Identifier: MIT
#include "app/robot_assembly.h"
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
  endpoints.credentials = o.credentials;
  try {
    p->server = std::make_unique<link::LinkServer>(endpoints);
  } catch (const std::exception& e) {
    *error = "cannot open the link on ports " + std::to_string(o.port) + ".." + std::to_string(o.port + 3) + ": " +
             e.what();
    *exit_code = 2;
    return nullptr;
  }
  // The calibration in use, applied and reverted live by the console (link apply_calibration).
  p->calibration_in_use = std::make_unique<robot::head::CalibrationInUse>(p->calibration, "--calib " + o.calib_path, p->clock);
  if (!o.calib_save.empty()) p->calibration_in_use->setSavePath(o.calib_save);
  record::LinkRecorderOptions recording;
  recording.mcap.compression = *record::parseCompression(o.record_compression);
  recording.metadata = {{"arm", p->arm_description}, {"cameras", o.syntheticCameras() ? "synthetic" : "aravis"},
                        {"calibration_file", o.calib_path}};
  p->recording = std::make_unique<robot::services::RecordingSwitch>(*p->server, o.record_dir, recording);
  p->recording->setCalibrationSource([in_use = p->calibration_in_use.get()] {
    link::proto::CalibrationInUse c;
    in_use->fill(&c);
    return std::optional(c);
  });
  if (!o.record_path.empty() && !p->recording->startFile(o.record_path, error)) {
    *error = "--record: " + *error;
    return nullptr;
  }
  robot::head::HeadLoopConfig loop_config;
  loop_config.calibration = p->calibration_in_use.get();
  loop_config.auto_nominal = o.auto_nominal;
  loop_config.sphere_radius = o.sphere_radius;
  if (!o.depth_proxy.empty()) loop_config.depth_proxy = link::parseDepthProxy(o.depth_proxy);
  loop_config.telemetry = &p->telemetry;
  p->loop = std::make_unique<robot::head::HeadLoop>(*p->arm, *p->controller, *p->joints, *p->server, p->clock, loop_config);

  if (!makeCameras(*p, exit_code, error)) return nullptr;

  robot::stereo::StereoPairerOptions pairing;
  pairing.tolerance_ns = static_cast<std::int64_t>(0.25e9 / o.fps);  // a quarter period
  p->pairs = std::make_unique<robot::stereo::StereoPairSource>(*p->left, *p->right, pairing);
  robot::video::PreviewOptions preview_options;
  preview_options.max_width = o.preview_width;
  preview_options.rate_hz = o.preview_hz > 0 ? o.preview_hz : 1.0;
  p->preview = std::make_unique<robot::video::PreviewStreamer>(*p->server, preview_options);
  if (!o.truth_path.empty() && !(p->truth_log = robot::stereo::GroundTruthLog::open(o.truth_path, *p->truth, error))) {
    *exit_code = 1;
    return nullptr;
  }
  p->stills = std::make_unique<robot::stereo::StereoStillTaker>(*p->joints, p->clock,
                                                        p->manipulator ? &p->manipulator_reports : nullptr);
  robot::video::VideoStreamerConfig video_config;
  if (o.media) {
    link::media::MediaSenderOptions media_options;
    media_options.port = static_cast<std::uint16_t>(o.port + link::LinkEndpoints::kMedia);
    media_options.rate.initial_bps = std::max(o.media_start_mbit * 1e6, media_options.rate.min_bps);
    // Head targets on the media path go where the ZeroMQ uplink's go (newest by stamp wins).
    media_options.on_head_target = [server = p->server.get()](const link::proto::HeadTarget& target) {
      server->offerHeadTarget(target);
    };
    // With keys every datagram is sealed with a session key the seated operator asks for over the
    // authenticated control channel (ControlRequest.open_media_session; DESIGN.md §10).
    media_options.sealed = o.credentials.secure();
    p->media = link::media::MediaSender::start(media_options, error);
    if (!p->media) {
      *error = "cannot open the media path on UDP port " + std::to_string(media_options.port) + " (--no-media runs without): " +
               *error;
      *exit_code = 1;
      return nullptr;
    }
    if (o.media_cap_mbit > 0) p->media->setCapBps(o.media_cap_mbit * 1e6);
    if (media_options.sealed) {
      // The seat handed over: the media session of the operator before ends with it (a key
      // nobody holds); the newly seated one asks for its own.
      p->server->setOperatorSeatHandler([media = p->media.get()](const std::string&) {
        media->setSealKey(link::media::newMediaSealKey());
      });
    }
    video_config.media = p->media.get();
    video_config.adaptive.nominal_fps = o.fps;
  }
  video_config.jpeg.quality = o.quality;
  video_config.jpeg.subsampling = o.subsampling == "444"   ? robot::video::ChromaSubsampling::k444
                                  : o.subsampling == "422" ? robot::video::ChromaSubsampling::k422
                                                           : robot::video::ChromaSubsampling::k420;
  video_config.codec = link::parseVideoCodec(o.codec).value_or(link::VideoCodec::kMjpeg);
  video_config.video.bit_rate_bps = static_cast<std::int64_t>(o.video_mbit * 1e6);
  video_config.video.fps = std::max(1, static_cast<int>(std::lround(o.fps)));
  video_config.video.key_frame_interval = o.key_frame_interval;
  video_config.video.prefer_gpu = o.video_gpu;
  video_config.telemetry = &p->telemetry;
  video_config.on_sent = [parts = p.get()](const robot::stereo::StereoFrame& pair, std::uint64_t sequence) {
    parts->stills->offer(pair, sequence);
    if (parts->options.preview_hz > 0) parts->preview->offer(pair, sequence);
    if (parts->truth_log) parts->truth_log->frameSent(pair, sequence, parts->loop->nominalMapping());
  };
  // Camera poses at capture time through the calibration in use; before any joint state, the
  // pose at the initial configuration.
  const robot::video::StereoPosesAt poses = [parts = p.get()](std::int64_t left_ns, std::int64_t right_ns) {
    return parts->calibration_in_use->posesAt(*parts->joints, parts->q_initial, left_ns, right_ns);
  };
  p->video = std::make_unique<robot::video::VideoStreamer>(*p->pairs, *p->server, p->clock, poses, video_config);
  p->control = std::make_unique<robot::services::RobotControl>(*p->loop, p->video.get(), p->stills.get(),
                                                     std::chrono::milliseconds(o.still_timeout_ms),
                                                     p->calibration_in_use.get(), p->recording.get());
  robot::services::RobotHealthSources health_sources;
  health_sources.cameras = {p->left.get(), p->right.get()};
  health_sources.pairs = p->pairs.get();
  health_sources.video = p->video.get();
  health_sources.loop = p->loop.get();
  health_sources.control = p->control.get();
  health_sources.server = p->server.get();
  health_sources.telemetry = &p->telemetry;
  health_sources.recording = p->recording.get();
  health_sources.arm = p->arm_description;
  health_sources.xarm = dynamic_cast<const robot::arm::XArmHeadArm*>(p->arm.get());
  health_sources.cameras_kind = o.syntheticCameras() ? "synthetic" : "aravis";
  p->health = std::make_unique<robot::services::RobotHealthReporter>(health_sources, p->clock);
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
         std::to_string(o.port) +
         (parts_->media ? ", media path on UDP port " + std::to_string(parts_->media->port()) : std::string());
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
  std::uint64_t frames_before = 0, bytes_before = 0;
  bool gpu_reason_said = false;
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
      if (v.codec != link::VideoCodec::kMjpeg) {
        const double seconds = std::max(o.stats_period_s, 1e-3);
        char budget[96] = "";
        if (v.stream.limited_by == robot::video::StreamLimitedBy::kBitRate)
          std::snprintf(budget, sizeof budget, " (the media path's budget; nominal %.1f)",
                        double(p.video->videoBitRateBps()) * 1e-6);
        std::fprintf(stderr,
                     "telesphere-robot: video %s (%s), target %.1f Mbit/s%s, key frames %llu (%llu asked for by the "
                     "operator or the media path), %.1f kB per pair in the last %.0f s\n",
                     link::videoCodecName(v.codec), v.video.backend.c_str(),
                     double(v.video.bit_rate_bps > 0 ? v.video.bit_rate_bps : p.video->videoBitRateBps()) * 1e-6,
                     budget,
                     static_cast<unsigned long long>(v.video.key_frames),
                     static_cast<unsigned long long>(v.video.key_frames_requested),
                     v.frames_sent > frames_before ? double(v.bytes_sent - bytes_before) / double(v.frames_sent - frames_before) * 1e-3 : 0.0,
                     seconds);
        if (!v.video.gpu_fallback_reason.empty() && !gpu_reason_said) {
          std::fprintf(stderr, "telesphere-robot: no GPU encoder: %s\n", v.video.gpu_fallback_reason.c_str());
          gpu_reason_said = true;
        }
      }
      if (p.media) {
        const auto m = p.media->stats();
        std::fprintf(stderr,
                     "telesphere-robot: media path: %s, target %.1f Mbit/s, delivered %.1f Mbit/s, loss %.1f %%, "
                     "round trip %.0f ms, queue %.0f ms; stream %s%.0f Hz, scale %.2f, q%d (%s); frames sent %llu, superseded %llu\n",
                     p.media->hasReceiver() ? "receiver" : "no receiver", m.rate.target_bps * 1e-6,
                     m.rate.delivered_bps * 1e-6, 100 * m.rate.loss_fraction, m.rate.rtt_ms, m.rate.queue_delay_ms,
                     v.stream_adapted ? "" : "nominal ", v.stream.fps, v.stream.scale, v.stream.quality,
                     robot::video::streamLimitedByName(v.stream.limited_by),
                     static_cast<unsigned long long>(m.frames_sent), static_cast<unsigned long long>(m.frames_superseded));
      }
      frames_before = v.frames_sent;
      bytes_before = v.bytes_sent;
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
