// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr offscreen`: options, the run, the statistics table and JSON.
#include "app/xr_offscreen_command.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/operator_stats_json.h"
#include "calib/calibration_file.h"
#include "xr/frame_loop/offscreen_operator.h"
#include "xr/replay/offline_replay.h"

namespace telesphere::app {
namespace {

std::atomic<bool> g_offscreen_stop{false};
extern "C" void onOffscreenSignal(int) { g_offscreen_stop = true; }

}  // namespace

CLI::App* addOffscreenCommand(CLI::App& app, OffscreenCommandOptions& o) {
  CLI::App* c = app.add_subcommand(
      "offscreen", "operator loop without a headset: trajectory-driven head, EGL offscreen, stats");
  c->add_option("--calib", o.calib,
                 "system calibration (two cameras); with --replay it overrides the calibrations the recording holds");
  c->add_option("--host", o.host, "robot (telesphere-robot) address")->capture_default_str();
  c->add_option("--port", o.port, "robot link base port")->capture_default_str()->check(CLI::Range(1024, 65532));
  addVideoLinkOptions(*c, o.link);
  c->add_option("--trajectory", o.trajectory, "head poses CSV: t,px,py,pz,qx,qy,qz,qw (default: demo motion)");
  c->add_option("--eye-size", o.eye_size, "render size per eye WxH")->capture_default_str();
  c->add_option("--rate", o.rate_hz, "display rate, Hz")->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  c->add_option("--duration", o.duration_s, "seconds to run (0: until SIGINT); with --replay: recording seconds")
      ->default_str("10; with --replay the whole recording");
  c->add_option("--mode", o.mode, "full6d | orientation3d | fixed")->capture_default_str();
  c->add_option("--path", o.path, "exact | mesh | lut")->capture_default_str();
  c->add_option("--radius", o.radius, "sphere radius r, m")->capture_default_str();
  addXrDepthOptions(*c, o.depth, "until the robot (a replay: the recording) says otherwise");
  c->add_option("--out", o.out_dir, "folder for stats.json and eyes_last.png");
  c->add_option("--png-every", o.png_every, "also write eyes_NNNNN.png every N frames")->capture_default_str();
  c->add_option("--wait", o.wait_s, "seconds to wait for the first frame")->capture_default_str();
  c->add_option("--truth-out", o.truth_dir,
                "folder for the projection maps of every --truth-every-th frame (ground-truth check)");
  c->add_option("--truth-every", o.truth_every, "record every N-th frame's projection maps")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
  c->add_option("--replay", o.replay,
                "render this recording (telesphere-robot --record) offline, deterministically, instead of "
                "connecting to a robot; the head from its recorded head targets, or --trajectory")
      ->check(CLI::ExistingFile);
  c->add_option("--views", o.views,
                "with --replay: render only the views a live run logged (its --out folder's views.csv: the camera "
                "frame and head pose of each PNG), each under the live PNG's name, to compare the two")
      ->check(CLI::ExistingFile);
  return c;
}

namespace {

int fail(int code, const std::string& message) {
  std::cerr << "telesphere-xr offscreen: " << message << '\n';
  return code;
}

/// The rows live runs and replays share.
void printViewTable(const xr::frame_loop::OperatorViewStats& v) {
  std::printf("| figure | value |\n|---|---:|\n");
  std::printf("| display frames | %llu |\n| render ms p50 / p99 (both eyes) | %.1f / %.1f |\n",
              static_cast<unsigned long long>(v.frames), v.render_ms_p50, v.render_ms_p99);
  std::printf("| camera frames shown | %llu |\n", static_cast<unsigned long long>(v.stereo_frames_shown));
  std::printf("| image age p50 / p99 ms (capture → display) | %.1f / %.1f |\n", v.image_age_p50_ms,
              v.image_age_p99_ms);
  if (v.depth_proxy != "fixed")
    std::printf("| scene proxy; depth estimates (pairs skipped); last sweep ms; left radius m; tiles matched | %s; %llu (%llu); "
                "%.1f; %.2f; %.0f %% |\n",
                v.depth_proxy.c_str(), static_cast<unsigned long long>(v.depth_estimates),
                static_cast<unsigned long long>(v.depth_pairs_skipped), v.depth_sweep_ms, v.depth_radius_left_m,
                100.0 * v.depth_matched_fraction);
  if (v.depth_proxy != "fixed")
    std::printf("| left sweep: earlier images from the arm's motion; longest baseline mm; tiles they decided | %d; %.0f; %d |\n",
                v.depth_motion_views_left, 1e3 * v.depth_motion_baseline_left_m, v.depth_tiles_decided_by_motion_left);
  if (v.depth_proxy != "fixed" && (v.depth_sweep_on_gpu || !v.depth_gpu_unavailable.empty()))
    std::printf("| the pair's costs | %s |\n",
                v.depth_sweep_on_gpu ? "on the GPU" : ("on the CPU: the GPU was asked for, " + v.depth_gpu_unavailable).c_str());
  if (v.depth_proxy != "fixed")
    std::printf("| images shown with their own depth; held for it (wait p50 / p99 ms); shown when the wait ran out | "
                "%llu; %llu (%.1f / %.1f); %llu |\n",
                static_cast<unsigned long long>(v.depth_images_with_own_depth),
                static_cast<unsigned long long>(v.depth_images_held), v.depth_hold_ms_p50, v.depth_hold_ms_p99,
                static_cast<unsigned long long>(v.depth_hold_timeouts));
  if (v.video_link == "udp")
    std::printf("| media path: datagrams, frames whole / with lost bands / lost | %llu, %llu / %llu / %llu |\n"
                "| lost bands; rows painted from the previous frame / left grey | %llu; %llu / %llu |\n",
                static_cast<unsigned long long>(v.media_datagrams), static_cast<unsigned long long>(v.media_frames_whole),
                static_cast<unsigned long long>(v.media_frames_concealed),
                static_cast<unsigned long long>(v.media_frames_lost), static_cast<unsigned long long>(v.media_bands_lost),
                static_cast<unsigned long long>(v.rows_concealed), static_cast<unsigned long long>(v.rows_grey));
}

int runReplay(const OffscreenCommandOptions& o, const std::optional<calib::SystemCalibration>& calibration,
              const xr::frame_loop::PacedOutputOptions& display, const xr::render::RenderSettings& render) {
  xr::replay::OfflineReplayOptions options;
  options.recording = o.replay;
  options.display = display;
  options.render = render;
  options.duration_s = std::max(0.0, o.duration_s);
  options.png_dir = o.out_dir;
  options.png_every_frames = o.png_every;
  options.depth_proxy = *link::parseDepthProxy(o.depth.proxy);  // until the recording says otherwise
  options.depth = depthWorkerOptions(o.depth);  // the replay's worker stays on its thread (the same estimates run after run)
  // A progress line on stderr every 5 s of wall time: offline rendering of a long 4K session takes a while.
  auto last_progress = std::chrono::steady_clock::now();
  options.progress = [&](double rendered_s, double total_s) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_progress < std::chrono::seconds(5)) return;
    last_progress = now;
    std::fprintf(stderr, "telesphere-xr offscreen: replay %.1f / %.1f s of the recording\n", rendered_s, total_s);
  };
  std::string error;
  if (!o.trajectory.empty()) {
    options.trajectory = xr::frame_loop::HeadTrajectory::load(o.trajectory, &error);
    if (!options.trajectory) return fail(1, error);
  }
  if (!o.views.empty()) {
    if (!o.trajectory.empty()) return fail(1, "--views brings the live run's head poses: not with --trajectory");
    if (o.out_dir.empty()) return fail(1, "--views renders PNGs: give --out DIR");
    auto views = xr::frame_loop::loadLoggedViews(o.views, &error);
    if (!views) return fail(1, error);
    if (views->empty()) return fail(1, o.views + ": no views (was the live run given --png-every?)");
    options.views = std::move(*views);
  }
  const auto stats = xr::replay::runOfflineReplay(calibration, options, g_offscreen_stop, &error);
  if (!stats) return fail(error.find("EGL") != std::string::npos ? 2 : 3, error);
  const xr::frame_loop::OperatorViewStats& v = stats->view;
  printViewTable(v);
  std::printf("| recording rendered, s | %.2f |\n| recorded frames read / undecodable | %llu / %llu |\n",
              stats->recording_s, static_cast<unsigned long long>(stats->recorded_frames),
              static_cast<unsigned long long>(stats->undecodable));
  std::printf("| calibration | %s%s |\n",
              calibration ? ("--calib " + o.calib + ", " + stats->calibration).c_str() : stats->calibration.c_str(),
              v.calibration_changes > 0 ? (", " + std::to_string(v.calibration_changes) + " change(s) replayed to generation " +
                                           std::to_string(v.calibration_generation)).c_str()
                                        : "");
  std::printf("| head | %s |\n| nominal pose from the recording | %s |\n",
              options.trajectory       ? o.trajectory.c_str()
              : !options.views.empty() ? ("the live run's, " + o.views).c_str()
                                       : (std::to_string(stats->head_targets) + " recorded head targets").c_str(),
              !v.nominal_from_robot ? "no"
              : stats->first_frame_with_nominal > 0
                  ? ("yes, from display frame " + std::to_string(stats->first_frame_with_nominal)).c_str()
                  : "yes");
  std::string missing;
  for (const std::uint64_t sequence : stats->views_missing) missing += " " + std::to_string(sequence);
  if (!options.views.empty())
    std::printf("| views rendered / camera frame not in the recording | %llu / %zu%s |\n",
                static_cast<unsigned long long>(stats->views_rendered), options.views.size() - stats->views_rendered,
                missing.empty() ? "" : (" (frames" + missing + ")").c_str());
  if (!o.out_dir.empty()) {
    nlohmann::json j = operatorStatsJson(v);
    j.update({{"frames", v.frames},
              {"frames_with_image", v.frames_with_image},
              {"recording_s", stats->recording_s},
              {"recorded_frames", stats->recorded_frames},
              {"undecodable", stats->undecodable},
              {"awaiting_key_frame", stats->awaiting_key_frame},
              {"replaced_unshown", stats->replaced_unshown},
              {"head_targets", stats->head_targets},
              {"first_frame_with_nominal", stats->first_frame_with_nominal},
              {"skipped", stats->skipped},
              {"calibration", calibration ? "--calib " + o.calib : stats->calibration},
              {"calibration_generation", v.calibration_generation},
              {"calibration_changes", v.calibration_changes},
              {"views", options.views.size()},
              {"views_rendered", stats->views_rendered}});
    std::ofstream(o.out_dir + "/stats.json") << j.dump(2) << '\n';
  }
  return 0;
}

}  // namespace

int runOffscreenCommand(const OffscreenCommandOptions& o) {
  std::optional<calib::SystemCalibration> calibration;
  if (!o.calib.empty()) {
    auto loaded = calib::loadCalibrationFile(o.calib);
    if (!loaded) return fail(1, loaded.error().describe());
    calibration = std::move(*loaded);
  } else if (o.replay.empty()) {
    return fail(1, "--calib FILE is needed (a replay takes the recording's own)");
  }
  std::string error;
  xr::frame_loop::PacedOutputOptions display;
  if (std::sscanf(o.eye_size.c_str(), "%dx%d", &display.eye_width, &display.eye_height) != 2 ||
      display.eye_width <= 0 || display.eye_height <= 0 || display.eye_width > 8192 || display.eye_height > 8192)
    return fail(1, "--eye-size '" + o.eye_size + "' is not WxH (1..8192)");
  display.rate_hz = o.rate_hz;
  const auto render = xr::render::renderSettingsFromText(o.mode, o.path, o.radius, &error, o.depth.grid_edges);
  if (!render) return fail(1, error);
  if (!o.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec) return fail(1, o.out_dir + ": " + ec.message());
  }
  std::signal(SIGINT, onOffscreenSignal);
  std::signal(SIGTERM, onOffscreenSignal);
  if (!o.replay.empty()) return runReplay(o, calibration, display, *render);

  std::optional<xr::frame_loop::HeadTrajectory> trajectory =
      o.trajectory.empty() ? std::optional<xr::frame_loop::HeadTrajectory>(xr::frame_loop::HeadTrajectory::demo())
                           : xr::frame_loop::HeadTrajectory::load(o.trajectory, &error);
  if (!trajectory) return fail(1, error);
  xr::frame_loop::OffscreenOperatorOptions options;
  options.endpoints.host = o.host;
  options.endpoints.base_port = o.port;
  options.endpoints.credentials = o.link.credentials;
  options.warn_insecure_link = o.link.security.insecure;
  options.display = display;
  options.duration_s = o.duration_s < 0 ? 10.0 : o.duration_s;
  options.render = *render;
  options.png_every_frames = o.png_every;
  options.truth_dir = o.truth_dir;
  options.truth_every_frames = o.truth_every;
  options.wait_first_frame = std::chrono::milliseconds(static_cast<long long>(o.wait_s * 1000.0));
  options.png_dir = o.out_dir;
  options.media_link = o.link.video_link == "udp";
  options.media_port = o.link.media_port;
  options.media_repair = o.link.media_repair == "on";
  options.head_targets_on_zmq = o.link.head_link == "both";
  options.depth_proxy = *link::parseDepthProxy(o.depth.proxy);
  options.depth_hold_ms = o.depth.hold_ms;
  options.depth = depthWorkerOptions(o.depth);
  const auto stats = xr::frame_loop::runOffscreenOperator(*calibration, *trajectory, options, g_offscreen_stop, &error);
  if (!stats) return fail(error.find("EGL") != std::string::npos || error.find("no stereo frame") != std::string::npos ? 2 : 3, error);

  const xr::frame_loop::OperatorViewStats& v = stats->view;
  printViewTable(v);
  std::printf("| fps | %.1f |\n| missed frames at %.0f Hz | %llu |\n", stats->fps, o.rate_hz,
              static_cast<unsigned long long>(stats->missed_frames));
  std::printf("| head targets sent | %llu |\n| nominal pose from the robot | %s |\n",
              static_cast<unsigned long long>(v.head_targets_sent), v.nominal_from_robot ? "yes" : "no");
  if (!o.out_dir.empty()) {
    nlohmann::json j = operatorStatsJson(v);
    j.update({{"frames", v.frames}, {"fps", stats->fps}, {"missed_frames", stats->missed_frames}});
    std::ofstream(o.out_dir + "/stats.json") << j.dump(2) << '\n';
  }
  return 0;
}

}  // namespace telesphere::app
