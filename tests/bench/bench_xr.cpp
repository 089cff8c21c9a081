// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench xr`: the operator app's frame loop offscreen (EGL surfaceless, this
///        machine's GL) at headset resolution per eye, fed on loopback by a robot-side video
///        path replaying 2×4K frames at 45 Hz: sustained frame rate, render time per frame (both
///        eyes, upload included), missed display frames at 90 Hz, and the age of the displayed
///        image (capture → display) p50/p99; per render path, the speed/accuracy knob.
#include <atomic>
#include <chrono>
#include <thread>

#include "tests/bench/bench_table.h"
#include "tests/bench/bench_topic.h"
#include "tests/bench/prerendered_frames.h"
#include "tests/bench/replay_video_source.h"
#include "xr/offscreen_operator.h"

namespace telesphere::bench {
namespace {

struct XrBenchCase {
  xr::RenderPath path;
  int eye_width, eye_height;
};

nlohmann::json runXrBench(const BenchContext& ctx) {
  const int cam_w = 3840, cam_h = 2160;
  const double seconds = ctx.quick ? 3.0 : 10.0;
  ctx.out << "xr: rendering 2×4K camera frames…\n" << std::flush;
  const auto left_frames = prerender(cam_w, cam_h, 0.032, ctx.quick ? 1 : 2);
  const auto right_frames = prerender(cam_w, cam_h, -0.032, ctx.quick ? 1 : 2);

  std::vector<XrBenchCase> cases = {{xr::RenderPath::kExact, 1440, 1600}};
  if (!ctx.quick) {
    cases.push_back({xr::RenderPath::kMesh, 1440, 1600});
    cases.push_back({xr::RenderPath::kLut, 1440, 1600});
    cases.push_back({xr::RenderPath::kExact, 720, 800});
  }
  Table table({"path", "eye px", "fps", "render ms p50", "p99", "missed @90 Hz", "camera frames shown",
               "image age p50 ms", "p99"});
  nlohmann::json json;
  int port = 27600;
  for (const XrBenchCase& c : cases) {
    ctx.out << "xr: " << xr::renderPathName(c.path) << " " << c.eye_width << "x" << c.eye_height << "…\n"
            << std::flush;
    link::LinkEndpoints endpoints;
    endpoints.base_port = port;
    port += 10;
    const robot::CameraPoseAt poses = [](robot::CameraSide side, std::int64_t) {
      return std::optional<Eigen::Isometry3d>(forwardCameraPose(side == robot::CameraSide::kLeft ? 0.032 : -0.032));
    };
    ReplayVideoSource robot_side(endpoints, left_frames, right_frames, 45.0, poses, std::chrono::milliseconds(0));
    std::string error;

    xr::OffscreenOperatorOptions options;
    options.endpoints = endpoints;
    options.eye_width = c.eye_width;
    options.eye_height = c.eye_height;
    options.duration_s = seconds;
    options.render.path = c.path;
    const std::atomic<bool> stop{false};
    const auto stats = xr::runOffscreenOperator(simulatedRig(cam_w, cam_h), xr::HeadTrajectory::demo(8.0),
                                                options, stop, &error);
    if (!stats) {
      ctx.out << "xr: " << error << '\n';
      json["error"] = error;
      continue;
    }
    table.addRow({std::string(xr::renderPathName(c.path)), std::to_string(c.eye_width) + "x" + std::to_string(c.eye_height),
                  formatNumber(stats->fps), formatNumber(stats->render_ms_p50), formatNumber(stats->render_ms_p99),
                  std::to_string(stats->missed_frames), std::to_string(stats->stereo_frames_shown),
                  formatNumber(stats->image_age_p50_ms), formatNumber(stats->image_age_p99_ms)});
    if (&c == &cases.front()) {
      json["fps"] = stats->fps;
      json["render_ms"] = stats->render_ms_p50;
      json["render_ms_p99"] = stats->render_ms_p99;
      json["missed_frames"] = stats->missed_frames;
      json["image_age_p50_ms"] = stats->image_age_p50_ms;
      json["image_age_p99_ms"] = stats->image_age_p99_ms;
      json["pose_to_display_ms"] = stats->pose_to_display_ms;
      json["upload_ms"] = stats->upload_ms_p50;
    }
  }
  ctx.out << "\nOffscreen operator loop, 2×4K JPEG input at 45 Hz on loopback, paced at 90 Hz, "
          << seconds << " s each\n";
  table.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(xr, telesphere::bench::BenchTopic{
                               "xr",
                               "operator frame loop offscreen: fps, render ms, missed frames, "
                               "image age, per render path",
                               {},
                               telesphere::bench::runXrBench});
