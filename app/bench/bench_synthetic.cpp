// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench synthetic`: what a SyntheticCamera costs. Renders defaultScene() from
///        the demo's head pose through the simulated rig's double-sphere lens (calib/data/
///        sim_calibration.yaml: fx = fy = 930 px at 3840×2160, scaled with the resolution) at
///        640×480, 1280×1024, 1920×1080 and 3840×2160 (quick: the first two), supersampling 1
///        and 2 (the speed/accuracy knob), with the camera's own row threads, the wrist marker
///        moving between frames. Prints wall ms per frame (median), the fps that gives, the CPU
///        ms per frame summed over the render threads (what the frame costs on an idle machine
///        and independent of other load: wall ≈ CPU / threads when the cores are free), and the
///        one-off set-up (ray table) time and memory.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#include "robot/clock/sim_clock.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"

namespace telesphere::bench {
namespace {

int& syntheticThreads() {
  static int threads = 2;
  return threads;
}

/// The sim rig's lens (ds, xi −0.18, alpha 0.59; fx 930 at 3840 px wide) scaled to `width`.
calib::GenericCamera syntheticBenchLens(int width, int height) {
  const double s = width / 3840.0;
  Eigen::VectorXd p(6);
  p << 930.0 * s, 930.0 * s, (width - 1) / 2.0, (height - 1) / 2.0, -0.18, 0.59;
  return *calib::GenericCamera::create("ds", p);
}

Eigen::Isometry3d syntheticBenchHeadPose(std::int64_t /*t_ns*/) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // optical z along +x of the robot, y down
  T.translation() = robot::cameras::DefaultSceneLayout{}.head_position;
  return T;
}

nlohmann::json runSynthetic(const BenchContext& ctx) {
  struct Size {
    int width, height;
  };
  std::vector<Size> sizes = {{640, 480}, {1280, 1024}, {1920, 1080}, {3840, 2160}};
  if (ctx.quick) sizes.resize(2);
  const int threads = std::max(1, syntheticThreads());
  auto scene = std::make_shared<robot::cameras::SyntheticScene>(robot::cameras::defaultScene());
  robot::clock::SimClock clock;
  nlohmann::json json;
  json["threads"] = threads;
  json["hardware_threads"] = std::thread::hardware_concurrency();
  ctx.out << "SyntheticCamera: defaultScene() from the demo head, ds lens of the sim rig scaled to "
             "each resolution, "
          << threads << " render thread(s) (" << std::thread::hardware_concurrency()
          << " hardware threads); median of the frames:\n";
  Table table({"resolution", "supersampling", "render (ms)", "fps", "CPU (ms)", "set-up (ms)", "rays (MB)"});
  for (const Size& size : sizes) {
    for (int n : {1, 2}) {
      robot::cameras::SyntheticCameraOptions options;
      options.supersampling = n;
      options.threads = threads;
      const auto s0 = std::chrono::steady_clock::now();
      const robot::cameras::SyntheticCamera cam(syntheticBenchLens(size.width, size.height), size.width, size.height,
                                       scene, &syntheticBenchHeadPose, clock, options);
      const double setup_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s0).count();
      const double pixels = static_cast<double>(size.width) * size.height;
      const int frames = ctx.quick ? 2 : std::clamp(static_cast<int>(4e7 / (pixels * n * n)), 3, 15);
      std::vector<double> ms;
      double cpu_ms = 0.0;
      for (int f = 0; f < frames; ++f) {
        const std::clock_t c0 = std::clock();
        const auto t0 = std::chrono::steady_clock::now();
        const robot::cameras::CameraFrame frame = cam.renderAt(static_cast<std::int64_t>(f) * 22'222'222);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        cpu_ms += 1000.0 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC / frames;
        if (frame.pixels->empty()) ctx.out << "empty frame\n";
      }
      std::sort(ms.begin(), ms.end());
      const double median = ms[ms.size() / 2];
      const double rays_mb = pixels * n * n * 12.0 / 1e6;
      table.addRow({std::to_string(size.width) + "x" + std::to_string(size.height), std::to_string(n),
                    formatNumber(median), formatNumber(1000.0 / median), formatNumber(cpu_ms),
                    formatNumber(setup_ms),
                    formatNumber(rays_mb)});
      const std::string key = std::to_string(size.width) + (n == 1 ? "" : "_ss" + std::to_string(n));
      json["render_ms_" + key] = median;
      json["fps_" + key] = 1000.0 / median;
      json["cpu_ms_" + key] = cpu_ms;
      json["setup_ms_" + key] = setup_ms;
    }
  }
  table.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(synthetic, telesphere::bench::BenchTopic{
                                      "synthetic",
                                      "synthetic camera: render ms and fps per resolution and supersampling",
                                      [](CLI::App& sub) {
                                        sub.add_option("--threads", telesphere::bench::syntheticThreads(),
                                                       "render threads per frame (default 2)");
                                      },
                                      telesphere::bench::runSynthetic});
