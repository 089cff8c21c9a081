// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr openxr`: options, the GL context, the eye work (xr_openxr_eye_work.h), and the wiring of
///        xr::runOpenXrSessions (sessions, reconnect, the operator loop over an OpenXrOutput);
///        statistics.
#include "app/xr_openxr_command.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>
#include <vector>

#include "app/operator_stats_json.h"
#include "app/xr_openxr_eye_work.h"
#include "calib/calibration_file.h"
#include "shaders/egl_context.h"
#include "xr/desktop/desktop_window.h"
#include "xr/openxr/openxr_mirror.h"
#include "xr/openxr/openxr_output.h"
#include "xr/openxr/openxr_readback_log.h"
#include "xr/openxr/openxr_run.h"
#include "xr/openxr/openxr_session.h"
#include "xr/openxr/openxr_test_scene_view.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/frame_loop/operator_view.h"

namespace telesphere::app {
namespace {

std::atomic<bool> g_openxr_stop{false};
extern "C" void onOpenXrInterrupt(int) { g_openxr_stop = true; }

int openXrFail(int code, const std::string& message) {
  std::cerr << "telesphere-xr openxr: " << message << "\n";
  return code;
}

}  // namespace

CLI::App* addOpenXrCommand(CLI::App& app, OpenXrCommandOptions& x) {
  CLI::App* c = app.add_subcommand("openxr", "the operator app in a headset (OpenXR: SteamVR, Monado, ...)");
  c->add_option("--calib", x.calib, "system calibration (two cameras): show telesphere-robot's frames");
  c->add_flag("--test-scene", x.test_scene, "show the built-in test scene instead (no robot)");
  c->add_option("--host", x.host, "robot (telesphere-robot) address")->capture_default_str();
  c->add_option("--port", x.port, "robot link base port")->capture_default_str()->check(CLI::Range(1024, 65532));
  addVideoLinkOptions(*c, x.link);
  c->add_option("--frames", x.frames, "end the session after N submitted frames (0: until Ctrl-C)")
      ->capture_default_str();
  c->add_option("--readback-dir", x.readback_dir,
                "save every swapchain image as PNG plus poses.csv (the T_cam_eye, fov, size, camera frame, "
                "mode and radius each image was rendered with) and the camera images shown (YUV planes) here");
  c->add_option("--out", x.out_dir, "folder for stats.json at the end");
  c->add_option("--radius", x.radius, "sphere radius r (m) until the robot says otherwise")->capture_default_str();
  addXrDepthOptions(*c, x.depth, "until the robot says otherwise; P cycles them");
  c->add_option("--mode", x.mode, "full6d | orientation3d | fixed, until the robot says otherwise")
      ->capture_default_str();
  c->add_option("--path", x.path, "exact | mesh | lut")->capture_default_str();
  c->add_option("--swapchain-colour", x.colour, "auto | srgb | linear: swapchain format kind (auto prefers sRGB)")
      ->capture_default_str();
  c->add_option("--exit-timeout", x.exit_timeout_s,
                "seconds to wait for the runtime to end the session after an exit request")
      ->capture_default_str();
  c->add_option("--reconnect", x.reconnect_s,
                "seconds to wait for the runtime to come back when it goes away (0: exit with code 4)")
      ->capture_default_str()->check(CLI::Range(0.0, 86400.0));
  c->add_option("--binding", x.binding,
                 "auto | egl | glx: the OpenGL binding (auto: EGL where the runtime offers "
                 "XR_MNDX_egl_enable, else GLX in a window)")
      ->capture_default_str();
  c->add_flag("--mirror", x.mirror,
              "also show both eyes in a desktop window (needs an X display); its keys: N capture the "
              "nominal pose, M cycle the mode, P cycle the scene proxy, +/- sphere radius, Esc quit");
  return c;
}

int runOpenXrCommand(const OpenXrCommandOptions& o) {
  std::string error;
  const auto parsed = xr::render::renderSettingsFromText(o.mode, o.path, o.radius, &error, o.depth.grid_edges);
  if (!parsed) return openXrFail(1, error);
  xr::openxr::OpenXrOptions options;
  if (o.colour == "auto") options.colour = xr::openxr::SwapchainColour::kAuto;
  else if (o.colour == "srgb") options.colour = xr::openxr::SwapchainColour::kSrgb;
  else if (o.colour == "linear") options.colour = xr::openxr::SwapchainColour::kLinear;
  else return openXrFail(1, "--swapchain-colour must be auto, srgb or linear, got \"" + o.colour + "\"");
  if (o.frames < 0) return openXrFail(1, "--frames must be >= 0");
  if (o.test_scene == !o.calib.empty())
    return openXrFail(1, o.test_scene ? "give either --calib (the robot's frames) or --test-scene, not both"
                                      : "needs --calib FILE (show telesphere-robot's cameras) or --test-scene");
  if (!o.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec) return openXrFail(1, o.out_dir + ": cannot create the folder: " + ec.message());
  }

  // The GL context the session renders with: EGL (headless, or the mirror window's on X11) where
  // the runtime offers XR_MNDX_egl_enable, else GLX in a window (SteamVR).
  if (o.binding != "auto" && o.binding != "egl" && o.binding != "glx")
    return openXrFail(1, "--binding must be auto, egl or glx, got \"" + o.binding + "\"");
  bool glx = o.binding == "glx";
  if (o.binding == "auto") glx = !xr::openxr::openXrRuntimeOffers("XR_MNDX_egl_enable").value_or(true);
  std::unique_ptr<xr::desktop::DesktopWindow> window;
  std::unique_ptr<gl::EglContext> context;
  if (o.mirror || glx) {
    window = xr::desktop::DesktopWindow::create(1280, 720, "telesphere-xr openxr — mirror", &error,
                                       glx ? xr::desktop::DesktopContextApi::kGlx : xr::desktop::DesktopContextApi::kEgl);
    if (!window)
      return openXrFail(2, (glx ? "the GLX binding needs a window: " : "no mirror window: ") + error);
  } else {
    context = gl::EglContext::createSurfaceless(&error);
    if (!context) return openXrFail(2, "no OpenGL 4.5 context: " + error);
  }
  OpenXrEyeWork work(o, *parsed);
  if (const int code = work.prepare(&error)) return openXrFail(code, error);
  xr::openxr::OpenXrOutput output([&](const xr::openxr::OpenXrEye& eye, std::string* eye_error) { return work.afterEye(eye, eye_error); },
                          [&](const xr::openxr::OpenXrEye& eye) { work.readBack(eye); });
  xr::frame_loop::OperatorLoop loop(work.scene(), output);

  xr::openxr::OpenXrRunOptions run_options;
  run_options.session = options;
  run_options.frames = std::uint64_t(o.frames);
  run_options.exit_timeout_s = o.exit_timeout_s;
  run_options.reconnect_s = o.reconnect_s;
  xr::openxr::OpenXrRunHooks hooks;
  if (window) hooks.between_frames = [&] { return work.betweenFrames(*window); };
  hooks.capture_nominal = [&] {
    if (!work.view()) return;
    std::cout << "controller: capture the nominal pose" << std::endl;
    work.view()->requestCaptureNominal();
  };
  hooks.session_started = [&](const xr::openxr::OpenXrSession& session, int number) {
    work.newSession(number);
    std::cout << "session " << number << ": runtime: " << session.runtimeName() << "; system: " << session.systemName()
              << "; binding: " << session.graphicsBinding() << "; space: " << session.referenceSpace()
              << "; swapchain: " << xr::openxr::glFormatName(session.swapchainFormat().format) << " " << session.eyeWidth()
              << "x" << session.eyeHeight() << " per eye" << std::endl;
  };
  hooks.note = [](const std::string& line, bool is_error) {
    if (is_error) std::cerr << "telesphere-xr openxr: " << line << std::endl;
    else std::cout << line << std::endl;
  };

  std::signal(SIGINT, onOpenXrInterrupt);
  std::signal(SIGTERM, onOpenXrInterrupt);
  const auto t0 = std::chrono::steady_clock::now();
  const xr::openxr::OpenXrRunResult run = xr::openxr::runOpenXrSessions(output, loop, run_options, hooks, g_openxr_stop);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  int code = 0;
  switch (run.end) {
    case xr::openxr::OpenXrRunEnd::kFinished: break;
    case xr::openxr::OpenXrRunEnd::kFailed: code = openXrFail(3, run.error); break;
    case xr::openxr::OpenXrRunEnd::kRuntimeGone: code = openXrFail(4, run.error); break;
    case xr::openxr::OpenXrRunEnd::kNoRuntime: code = openXrFail(5, run.error); break;
  }
  if (run.sessions == 0) return code;  // the one message above says why
  std::cout << "frames: requested " << o.frames << ", waited " << run.waited << ", submitted " << run.submitted
            << " with a projection layer, " << run.not_rendered
            << " ended without layers (not visible or pose invalid), " << loop.stats().missed_frames
            << " display periods missed\n";
  std::cout << "sessions: " << run.sessions << "\n";
  std::cout << "states: " << (run.states.empty() ? std::string("(none)") : run.states) << "\n";
  std::cout << "focused: " << (run.focused_ever ? "yes" : "no") << std::endl;
  nlohmann::json j = {{"sessions", run.sessions},
                      {"frames_requested", o.frames},
                      {"frames_waited", run.waited},
                      {"frames_submitted", run.submitted},
                      {"frames_without_layers", run.not_rendered},
                      {"missed_frames", loop.stats().missed_frames},
                      {"fps", run.fps},
                      {"run_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()},
                      {"focused", run.focused_ever}};
  if (xr::frame_loop::OperatorView* view = work.view()) {
    const xr::frame_loop::OperatorViewStats s = view->stats();
    std::cout << "robot frames: " << s.stereo_frames_shown << " shown; image age p50/p99 " << s.image_age_p50_ms
              << "/" << s.image_age_p99_ms << " ms; head-pose → display " << s.pose_to_display_ms_p50
              << " ms; head targets sent " << s.head_targets_sent << "; nominal from the robot "
              << (s.nominal_from_robot ? "yes" : "no") << "; settings changes " << s.settings_changes << std::endl;
    j.update(operatorStatsJson(s));
  }
  if (!o.out_dir.empty()) {
    std::ofstream(o.out_dir + "/stats.json") << j.dump(2) << '\n';
    if (window && o.mirror && !work.mirror().save(*window, o.out_dir + "/mirror_last.png", &error))
      std::cerr << "telesphere-xr openxr: mirror_last.png: " << error << "\n";
  }
  return code;
}

}  // namespace telesphere::app
