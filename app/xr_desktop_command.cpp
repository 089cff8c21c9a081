// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr desktop`: options, the window as the operator loop's output, keys → head
///        and robot requests between frames, statistics.
#include "app/xr_desktop_command.h"

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
#include "xr/frame_loop/eyes_png.h"
#include "xr/desktop/desktop_window.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/frame_loop/operator_view.h"
#include "xr/frame_loop/paced_output.h"
#include "xr/desktop/virtual_head.h"

namespace telesphere::app {
namespace {

std::atomic<bool> g_desktop_stop{false};
extern "C" void onDesktopSignal(int) { g_desktop_stop = true; }

bool desktopParseSize(const std::string& text, int& w, int& h) {
  return std::sscanf(text.c_str(), "%dx%d", &w, &h) == 2 && w > 0 && h > 0 && w <= 8192 && h <= 8192;
}

/// The window as the operator loop's output: both eyes presented side by side.
class DesktopOutput final : public xr::frame_loop::PacedOutput {
 public:
  DesktopOutput(const xr::frame_loop::PacedOutputOptions& options, HeadAt head, xr::desktop::DesktopWindow& window)
      : PacedOutput(options, std::move(head)), window_(window) {}

 protected:
  bool present(std::string* error) override {
    return window_.present(left().framebuffer(), right().framebuffer(), options().eye_width, options().eye_height,
                           error);
  }

 private:
  xr::desktop::DesktopWindow& window_;
};

}  // namespace

CLI::App* addDesktopCommand(CLI::App& app, DesktopCommandOptions& o) {
  CLI::App* c = app.add_subcommand(
      "desktop", "operator app in a window: mouse and keyboard move the head (needs an X display)");
  c->add_option("--calib", o.calib, "system calibration (two cameras)")->required();
  c->add_option("--host", o.host, "robot (telesphere-robot) address")->capture_default_str();
  c->add_option("--port", o.port, "robot link base port")->capture_default_str()->check(CLI::Range(1024, 65532));
  addVideoLinkOptions(*c, o.link);
  c->add_option("--eye-size", o.eye_size, "render size per eye WxH")->capture_default_str();
  c->add_option("--window-size", o.window_size, "window size WxH")->capture_default_str();
  c->add_option("--rate", o.rate_hz, "frames per second")->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  c->add_option("--duration", o.duration_s, "seconds to run (0: until closed)")->capture_default_str();
  c->add_option("--ipd", o.ipd, "distance between the eyes, m")->capture_default_str()->check(CLI::Range(0.0, 0.2));
  c->add_option("--mode", o.mode, "full6d | orientation3d | fixed, until the robot says otherwise")
      ->capture_default_str();
  c->add_option("--path", o.path, "exact | mesh | lut")->capture_default_str();
  c->add_option("--radius", o.radius, "sphere radius r (m), until the robot says otherwise")->capture_default_str();
  addXrDepthOptions(*c, o.depth, "until the robot says otherwise; P cycles them");
  c->add_option("--out", o.out_dir, "folder for stats.json and eyes_last.png at the end");
  return c;
}

int runDesktopCommand(const DesktopCommandOptions& o) {
  const auto fail = [](int code, const std::string& message) {
    std::cerr << "telesphere-xr desktop: " << message << '\n';
    return code;
  };
  int eye_w = 0, eye_h = 0, win_w = 0, win_h = 0;
  if (!desktopParseSize(o.eye_size, eye_w, eye_h)) return fail(1, "--eye-size '" + o.eye_size + "' is not WxH (1..8192)");
  if (!desktopParseSize(o.window_size, win_w, win_h))
    return fail(1, "--window-size '" + o.window_size + "' is not WxH (1..8192)");
  std::string error;
  const auto render = xr::render::renderSettingsFromText(o.mode, o.path, o.radius, &error, o.depth.grid_edges);
  if (!render) return fail(1, error);
  auto calibration = calib::loadCalibrationFile(o.calib);
  if (!calibration) return fail(1, calibration.error().describe());
  if (calibration->cameras.size() != 2) return fail(1, o.calib + ": the operator view needs two cameras");
  if (!o.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec) return fail(1, o.out_dir + ": " + ec.message());
  }

  auto window = xr::desktop::DesktopWindow::create(win_w, win_h, "telesphere-xr desktop", &error);
  if (!window) return fail(2, error);
  xr::desktop::VirtualHead head;
  xr::frame_loop::PacedOutputOptions paced;  // about 100° × 104° like the paper's headset, at this aspect
  paced.rate_hz = o.rate_hz;
  paced.ipd = o.ipd;
  paced.eye_width = eye_w;
  paced.eye_height = eye_h;
  DesktopOutput output(paced, [&](double) { return head.pose(); }, *window);
  if (!output.complete()) return fail(3, "cannot create " + o.eye_size + " eye targets");

  xr::frame_loop::OperatorViewOptions view_options;
  view_options.endpoints.host = o.host;
  view_options.endpoints.base_port = o.port;
  view_options.render = *render;
  applyXrDepthOptions(o.depth, view_options);
  applyVideoLinkOptions(o.link, view_options);
  xr::frame_loop::OperatorView view(*calibration, view_options);
  xr::frame_loop::OperatorLoop loop(view, output);
  std::cout << "telesphere-xr desktop: W/A/S/D walk, R/F up/down, drag with the left mouse button to look, "
               "N capture the nominal pose, M cycle the mode, P cycle the scene proxy (fixed, radius, grid), +/- sphere radius, "
               "Home reset, Esc quit"
            << std::endl;

  std::signal(SIGINT, onDesktopSignal);
  std::signal(SIGTERM, onDesktopSignal);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto last = t0, last_title = t0;
  std::uint64_t frames_at_title = 0;
  int code = 0;
  while (!g_desktop_stop.load() && !window->shouldClose()) {
    output.waitUntilDue();  // then the keys and mouse, so the frame's head pose is as fresh as can be
    const auto now = Clock::now();
    if (o.duration_s > 0 && now - t0 >= std::chrono::duration<double>(o.duration_s)) break;
    window->pollEvents();
    head.step(window->headInput(), std::chrono::duration<double>(now - last).count());
    last = now;
    const xr::desktop::DesktopCommands commands = window->takeCommands();
    if (commands.quit) break;
    if (commands.reset_head) head.reset();
    if (commands.capture_nominal) view.requestCaptureNominal();
    if (commands.cycle_mode) view.requestNextMode();
    if (commands.cycle_depth_proxy) view.cycleDepthProxy();
    if (commands.radius_up) view.requestRadiusScaled(1.25);
    if (commands.radius_down) view.requestRadiusScaled(1.0 / 1.25);
    if (!loop.step(&error)) {
      code = fail(3, error);
      break;
    }
    const auto done = Clock::now();
    if (done - last_title >= std::chrono::seconds(1)) {
      const std::uint64_t frames = loop.stats().frames;
      char title[256];
      const xr::render::RenderSettings& s = view.settings();
      char robot[64] = "";
      if (!view.hasImage())
        std::snprintf(robot, sizeof robot, " — waiting for the robot");
      else if (view.secondsWithoutNewFrame() > xr::frame_loop::OperatorView::kSilentRobotS)
        std::snprintf(robot, sizeof robot, " — robot silent for %.0f s", view.secondsWithoutNewFrame());
      std::snprintf(title, sizeof title, "telesphere-xr desktop — %.1f fps — %s, r %.2f m, proxy %s%s",
                    double(frames - frames_at_title) / std::chrono::duration<double>(done - last_title).count(),
                    std::string(telesphere::link::visualModeName(s.mode)).c_str(), s.radius,
                    std::string(link::depthProxyName(view.depthProxy())).c_str(), robot);
      window->setTitle(title);
      last_title = done;
      frames_at_title = frames;
    }
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  const xr::frame_loop::OperatorLoopStats loop_stats = loop.stats();
  const std::uint64_t frames = loop_stats.frames, missed = loop_stats.missed_frames;
  const xr::frame_loop::OperatorViewStats s = view.stats();
  std::printf("desktop: %llu frames, %.1f fps, render+present ms p50/p99 %.1f/%.1f, %llu missed at %.0f Hz, "
              "%llu camera frames shown, image age p50/p99 %.1f/%.1f ms, %llu head targets sent, nominal from the "
              "robot: %s\n",
              static_cast<unsigned long long>(frames), loop_stats.fps, s.render_ms_p50,
              s.render_ms_p99, static_cast<unsigned long long>(missed), o.rate_hz,
              static_cast<unsigned long long>(s.stereo_frames_shown), s.image_age_p50_ms, s.image_age_p99_ms,
              static_cast<unsigned long long>(s.head_targets_sent), s.nominal_from_robot ? "yes" : "no");
  if (!o.out_dir.empty()) {
    const Eigen::Vector3d p = head.position();
    nlohmann::json j = operatorStatsJson(s);
    j.update({{"frames", frames},
              {"fps", loop_stats.fps},
              {"missed_frames", missed},
              {"mode", std::string(telesphere::link::visualModeName(view.settings().mode))},
              {"radius", view.settings().radius},
              {"head_position", {p.x(), p.y(), p.z()}},
              {"head_yaw", head.yaw()},
              {"head_pitch", head.pitch()},
              {"last_control", view.lastControlResult()}});
    std::ofstream(o.out_dir + "/stats.json") << j.dump(2) << '\n';
    if (code == 0 && !xr::frame_loop::writeEyesPng(o.out_dir + "/eyes_last.png", output.left(), output.right(), &error))
      code = fail(3, error);
  }
  return code;
}

}  // namespace telesphere::app
