// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench xr`: the operator app's frame loop offscreen (EGL surfaceless, this
///        machine's GL) at headset resolution per eye, fed on loopback by a robot-side video
///        path replaying 2×4K frames at 45 Hz: sustained frame rate, render time per frame (both
///        eyes, upload included), missed display frames at 90 Hz, and the age of the displayed
///        image (capture → display) p50/p99; per render path, the speed/accuracy knob. With a
///        Monado root (--monado-root or TELESPHERE_MONADO_ROOT), also `telesphere-xr openxr`
///        against headless Monado fed by telesphere-robot: frames submitted vs requested.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "app/operator_stats_json.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/prerendered_frames.h"
#include "app/bench/replay_video_source.h"
#include "xr/frame_loop/offscreen_operator.h"

namespace telesphere::bench {
namespace {

std::string g_xr_bench_monado_root;

std::string xrBenchQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// telesphere-robot (simulated, 640×360 at 15 Hz) + `telesphere-xr openxr` under headless Monado
/// (null compositor, simulated HMD) for `frames` frames; the app's stats.json, or an error.
nlohmann::json runXrBenchMonado(const BenchContext& ctx, int frames) {
  namespace fs = std::filesystem;
  const fs::path bin = fs::read_symlink("/proc/self/exe").parent_path();
  const fs::path src = TELESPHERE_SOURCE_DIR;
  char dir_template[] = "/tmp/telesphere-bench-monado.XXXXXX";
  const char* dir = mkdtemp(dir_template);
  if (!dir) return {{"error", "cannot create a scratch folder"}};
  const std::string out = dir;
  const std::string command =
      // In a sanitizer build the side root's Mesa and loader leak; whose leaks are whose is
      // xr_openxr_monado_test's to judge (tests/xr/monado/leak_report.h), so LeakSanitizer only
      // reports here. Other sanitizer errors then exit 0 too: they are found in the log below.
      "LSAN_OPTIONS=exitcode=0 sh -c " +
      xrBenchQuote(xrBenchQuote((bin / "telesphere-robot").string()) +
                   " --insecure --sim --size 640x360 --fps 15 --port 27690 --duration 600 > " + xrBenchQuote(out + "/robot.log") +
                   " 2>&1 & r=$!; " + xrBenchQuote((src / "tests/xr/monado/run_with_monado.sh").string()) + " " +
                   xrBenchQuote(g_xr_bench_monado_root) + " -- " + xrBenchQuote((bin / "telesphere-xr").string()) +
                   " openxr --insecure --calib " + xrBenchQuote((src / "calib/data/sim_calibration.yaml").string()) +
                   " --port 27690 --frames " + std::to_string(frames) + " --out " + xrBenchQuote(out) + " > " +
                   xrBenchQuote(out + "/xr.log") + " 2>&1; rc=$?; kill -INT $r; wait $r; exit $rc");
  ctx.out << "xr: openxr against Monado (" << g_xr_bench_monado_root << "), " << frames << " frames…\n" << std::flush;
  const int status = std::system(command.c_str());
  nlohmann::json stats;
  std::ifstream in(out + "/stats.json");
  std::ifstream log(out + "/xr.log");
  std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  const bool sanitizer_error =
      text.find("ERROR: AddressSanitizer") != std::string::npos || text.find("runtime error:") != std::string::npos;
  if (status != 0 || !in || sanitizer_error) {
    if (text.size() > 2000) text = text.substr(text.size() - 2000);
    const std::string why = sanitizer_error ? "a sanitizer error in the app" : "status " + std::to_string(status);
    ctx.out << "xr: the Monado run failed (" << why << "):\n" << text << '\n';
    stats = {{"error", "the Monado run failed: " + why}};
  } else {
    in >> stats;
  }
  fs::remove_all(out);
  return stats;
}

struct XrBenchCase {
  xr::render::RenderPath path;
  int eye_width, eye_height;
  int upload_ring_slots = xr::frame_loop::StereoViewRenderer::kDefaultUploadSlots;  ///< 0: from the decoder's memory
};

nlohmann::json runXrBench(const BenchContext& ctx) {
  const int cam_w = 3840, cam_h = 2160;
  const double seconds = ctx.quick ? 3.0 : 10.0;
  ctx.out << "xr: rendering 2×4K camera frames…\n" << std::flush;
  const auto left_frames = prerender(cam_w, cam_h, 0.032, ctx.quick ? 1 : 2);
  const auto right_frames = prerender(cam_w, cam_h, -0.032, ctx.quick ? 1 : 2);

  // The first case is the default (its figures are the JSON's top level); the second is the
  // same without the upload ring, the knob the ring's figures are measured against.
  std::vector<XrBenchCase> cases = {{xr::render::RenderPath::kExact, 1440, 1600}, {xr::render::RenderPath::kExact, 1440, 1600, 0}};
  if (!ctx.quick) {
    cases.push_back({xr::render::RenderPath::kMesh, 1440, 1600});
    cases.push_back({xr::render::RenderPath::kLut, 1440, 1600});
    cases.push_back({xr::render::RenderPath::kExact, 720, 800});
  }
  Table table({"path", "eye px", "new image via", "fps", "render ms p50", "p99", "missed @90 Hz",
               "camera frames shown", "image age p50 ms", "p99", "upload ms (render thread) p50", "p99",
               "decode ms p50", "images in ring / own memory"});
  nlohmann::json json;
  int port = 27600;
  for (const XrBenchCase& c : cases) {
    ctx.out << "xr: " << xr::render::renderPathName(c.path) << " " << c.eye_width << "x" << c.eye_height << "…\n"
            << std::flush;
    link::LinkEndpoints endpoints;
    endpoints.base_port = port;
    port += 10;
    const robot::video::StereoPosesAt poses = [](std::int64_t, std::int64_t) {
      robot::head::StereoCameraPoses p;
      p.T_robot_cam_l = forwardCameraPose(0.032);
      p.T_robot_cam_r = forwardCameraPose(-0.032);
      p.measured_l = p.measured_r = true;
      return p;
    };
    ReplayVideoSource robot_side(endpoints, left_frames, right_frames, 45.0, poses, std::chrono::milliseconds(0));
    std::string error;

    xr::frame_loop::OffscreenOperatorOptions options;
    options.endpoints = endpoints;
    options.display.eye_width = c.eye_width;
    options.display.eye_height = c.eye_height;
    options.duration_s = seconds;
    options.render.path = c.path;
    options.upload_ring_slots = c.upload_ring_slots;
    const std::atomic<bool> stop{false};
    const auto stats = xr::frame_loop::runOffscreenOperator(simulatedRig(cam_w, cam_h), xr::frame_loop::HeadTrajectory::demo(8.0),
                                                options, stop, &error);
    if (!stats) {
      ctx.out << "xr: " << error << '\n';
      json["error"] = error;
      continue;
    }
    const xr::frame_loop::OperatorViewStats& v = stats->view;
    const std::string via = c.upload_ring_slots > 0 ? "ring of " + std::to_string(c.upload_ring_slots) : "decoder memory";
    table.addRow({std::string(xr::render::renderPathName(c.path)), std::to_string(c.eye_width) + "x" + std::to_string(c.eye_height),
                  via, formatNumber(stats->fps), formatNumber(v.render_ms_p50), formatNumber(v.render_ms_p99),
                  std::to_string(stats->missed_frames), std::to_string(v.stereo_frames_shown),
                  formatNumber(v.image_age_p50_ms), formatNumber(v.image_age_p99_ms),
                  formatNumber(v.upload_ms_render_thread_p50), formatNumber(v.upload_ms_render_thread_p99),
                  formatNumber(v.decode_ms_p50),
                  std::to_string(v.images_in_upload_slots) + " / " + std::to_string(v.images_in_own_memory)});
    if (&c == &cases.front()) {
      json.update(app::operatorStatsJson(v));
      json["fps"] = stats->fps;
      json["missed_frames"] = stats->missed_frames;
    } else if (c.upload_ring_slots == 0 && c.path == cases.front().path) {
      json["without_upload_ring"] = app::operatorStatsJson(v);
    }
  }
  ctx.out << "\nOffscreen operator loop, 2×4K JPEG input at 45 Hz on loopback, paced at 90 Hz, "
          << seconds << " s each\n";
  table.print(ctx.out);

  if (!g_xr_bench_monado_root.empty()) {
    const int frames = ctx.quick ? 40 : 400;
    const nlohmann::json m = runXrBenchMonado(ctx, frames);
    json["monado"] = m;
    if (!m.contains("error")) {
      Table monado({"frames requested", "waited", "submitted", "fps", "render ms p50", "p99", "missed periods",
                    "camera frames shown", "image age p50 ms", "p99", "head pose → display ms"});
      monado.addRow({std::to_string(frames), std::to_string(m.value("frames_waited", 0)),
                     std::to_string(m.value("frames_submitted", 0)), formatNumber(m.value("fps", 0.0)),
                     formatNumber(m.value("render_ms", 0.0)), formatNumber(m.value("render_ms_p99", 0.0)),
                     std::to_string(m.value("missed_frames", 0)), std::to_string(m.value("stereo_frames_shown", 0)),
                     formatNumber(m.value("image_age_p50_ms", 0.0)), formatNumber(m.value("image_age_p99_ms", 0.0)),
                     formatNumber(m.value("pose_to_display_ms", 0.0))});
      ctx.out << "\ntelesphere-xr openxr against Monado 25 (null compositor paces at 20 Hz, simulated HMD, "
                 "320×240 per eye), fed by telesphere-robot (simulated, 2×640×360 at 15 Hz)\n";
      monado.print(ctx.out);
    }
  }
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(xr, telesphere::bench::BenchTopic{
                               "xr",
                               "operator frame loop offscreen: fps, render ms, missed frames, "
                               "image age, per render path",
                               [](CLI::App& c) {
                                 const char* env = std::getenv("TELESPHERE_MONADO_ROOT");
                                 telesphere::bench::g_xr_bench_monado_root = env ? env : "";
                                 c.add_option("--monado-root", telesphere::bench::g_xr_bench_monado_root,
                                              "a Monado trixie root (tests/xr/monado/build_trixie_root.sh): "
                                              "also run telesphere-xr openxr against it (default "
                                              "$TELESPHERE_MONADO_ROOT)");
                               },
                               telesphere::bench::runXrBench});
