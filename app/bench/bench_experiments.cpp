// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench experiments`: the paper's quantitative experiments (§IV-A, Figs. 5–7,
///        the 40 ms image latency) re-run end to end on this machine, and what the operator sees
///        checked against the simulation's ground truth. Real processes on loopback:
///        telesphere-robot (simulated arm, synthetic cameras rendering at the arm's TRUE pose,
///        8 ms exposure, 10 ms transfer, --truth-out) and telesphere-xr offscreen (a scripted head:
///        still, then fast lateral moves of 0.25 m peaking at 0.5 m/s, --truth-out); this process
///        listens to the link's telemetry like the console does. From one run per sphere radius:
///          1. image latency capture → display per stage (XR telemetry stamps);
///          2. head-movement latency t1 / t2 (operator head speed from the XR app's display
///             frames, robot head speed from the measured joint states; paper Fig. 6);
///          3. Δs, left eye to left camera at capture, against v_op (paper Fig. 7);
///          5. the eye images' angular error against the truth (app/bench/truth) against head speed
///             and radius; at rest it must be near zero. Two more runs at r = 1 m with the XR app's
///             depth proxies from its own stereo sweep (--depth-proxy radius, grid; #35), with
///             their image latency against the fixed sphere's.
///        And in this process, on the GPU renderer: 4. γ against object distance for a 10 cm eye
///        offset at r = 1 m, measured on rendered projection maps, against eq. 4 (paper Fig. 5).
///        Writes CSV, PNG figures (QCustomPlot, as the console) and report.md under --out.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>
#include <numeric>
#include <thread>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "robot/head/head_motion_trace.h"
#include "robot/link/link_client.h"
#include "robot/link/link_pose.h"
#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/child_process.h"
#include "app/bench/figure_png.h"
#include "app/bench/head_motion_figure.h"
#include "app/bench/truth/eye_image_truth.h"
#include "xr/render/gpu_camera.h"
#include "xr/render/sphere_geometry.h"
#include "xr/render/spherical_renderer.h"

namespace telesphere::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string& experimentsOut() {
  static std::string dir = "bench-out/experiments";
  return dir;
}

constexpr double kMoveDistance = 0.25;                            // m, lateral (paper Fig. 6)
constexpr double kPeakSpeed = 0.5;                                // m/s
constexpr double kMoveDuration = 1.875 * kMoveDistance / kPeakSpeed;  // s, minimum jerk
constexpr double kStill = 3.0;                                    // s before the first move
constexpr double kHold = 1.6;                                     // s between moves
constexpr double kSpeedThreshold = 0.05;                          // m/s, 10 % of the peak
constexpr double kRestSpeed = 0.005;                              // m/s: "at rest" below
constexpr double kMovingSpeed = 0.1;                              // m/s: "moving" above
constexpr double kRestDsMm = 0.5;                                 // mm: and the arm has caught up

double minimumJerk(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return 10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5);
}

/// Lateral head offset (m, to the right) at t: still, then right, back, right, back … with holds.
double lateralOffset(double t, int moves) {
  double x = 0.0;
  for (int k = 0; k < moves; ++k) {
    const double start = kStill + k * (kMoveDuration + kHold);
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    x += sign * kMoveDistance * minimumJerk((t - start) / kMoveDuration);
  }
  return x;
}

double runDuration(int moves) { return kStill + moves * (kMoveDuration + kHold) + 0.5; }

bool writeTrajectory(const fs::path& path, int moves) {
  std::ofstream out(path);
  out << "t,px,py,pz,qx,qy,qz,qw\n";
  for (double t = 0.0; t <= runDuration(moves) + 1.0; t += 0.005)
    out << t << ',' << lateralOffset(t, moves) << ",1.6,0,0,0,0,1\n";
  return bool(out);
}

/// What one robot + XR run left behind.
struct LoopRun {
  double radius_m = 1.0;
  std::string proxy = "fixed";  ///< the XR app's --depth-proxy (radius, grid: from its stereo sweep)
  std::vector<link::proto::XrTelemetry> xr;
  std::vector<link::proto::RobotTelemetry> robot;
  fs::path robot_truth, xr_truth;
  std::string error;  ///< empty when the run worked
};

/// "r = 1 m" for the fixed sphere, else the proxy's name.
std::string runLabel(const LoopRun& run) {
  return run.proxy == "fixed" ? "r = " + formatNumber(run.radius_m) + " m" : run.proxy + " (stereo)";
}

LoopRun runLoop(const BenchContext& ctx, double radius_m, const std::string& proxy, int moves, int port, const fs::path& dir) {
  LoopRun run;
  run.radius_m = radius_m;
  run.proxy = proxy;
  fs::create_directories(dir);
  const fs::path bin = fs::read_symlink("/proc/self/exe").parent_path();
  const std::string calib = std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml";
  run.robot_truth = dir / "robot_truth.csv";
  run.xr_truth = dir / "xr_truth";
  if (!writeTrajectory(dir / "trajectory.csv", moves)) {
    run.error = "cannot write " + (dir / "trajectory.csv").string();
    return run;
  }
  const double duration = runDuration(moves);
  ctx.out << "experiments: " << runLabel(run) << ": robot + XR app for " << formatNumber(duration) << " s…\n"
          << std::flush;
  ChildProcess robot({(bin / "telesphere-robot").string(), "--insecure", "--sim", "--size", "320x180", "--fps", "30", "--port",
                      std::to_string(port), "--duration", "600", "--stats-period", "0", "--sphere-radius",
                      std::to_string(radius_m), "--render-threads", "1", "--preview-rate", "0", "--truth-out",
                      run.robot_truth.string()},
                     (dir / "robot.log").string());
  if (!robot.running()) {
    run.error = "cannot start " + (bin / "telesphere-robot").string();
    return run;
  }
  link::LinkEndpoints endpoints;
  endpoints.base_port = port;
  link::LinkClient client(endpoints, link::LinkClient::Options{.telemetry = true});
  ChildProcess xr({(bin / "telesphere-xr").string(), "offscreen", "--insecure", "--calib", calib, "--port", std::to_string(port),
                   "--eye-size", "160x176", "--rate", "59", "--duration", std::to_string(duration), "--trajectory",
                   (dir / "trajectory.csv").string(), "--out", (dir / "xr").string(), "--truth-out",
                   run.xr_truth.string(), "--truth-every", "6", "--wait", "60", "--depth-proxy", proxy},
                  (dir / "xr.log").string());
  const auto take = [&] {
    for (auto& envelope : client.takeTelemetry()) {
      if (envelope.has_xr_telemetry()) run.xr.push_back(std::move(*envelope.mutable_xr_telemetry()));
      if (envelope.has_robot_telemetry()) run.robot.push_back(std::move(*envelope.mutable_robot_telemetry()));
    }
  };
  const auto deadline = Clock::now() + std::chrono::duration<double>(duration + 90.0);
  std::optional<int> xr_code;
  while (!(xr_code = xr.wait(std::chrono::milliseconds(20))) && Clock::now() < deadline) take();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  take();
  const int robot_code = robot.stop();
  if (!xr_code || *xr_code != 0)
    run.error = "telesphere-xr offscreen " + (xr_code ? "exited with " + std::to_string(*xr_code) : "did not finish") +
                " (" + (dir / "xr.log").string() + ")";
  else if (robot_code != 0)
    run.error = "telesphere-robot exited with " + std::to_string(robot_code) + " (" + (dir / "robot.log").string() + ")";
  return run;
}

// --- Signals from the telemetry --------------------------------------------------------------

struct TimedPosition {
  double t_s;  ///< robot clock
  Eigen::Vector3d p;
};

/// Central-difference speeds (m/s) of positions sorted by time, at each sample's time.
std::vector<std::pair<double, double>> speeds(const std::vector<TimedPosition>& samples) {
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 1; i + 1 < samples.size(); ++i) {
    const double dt = samples[i + 1].t_s - samples[i - 1].t_s;
    if (dt <= 0) continue;
    out.emplace_back(samples[i].t_s, (samples[i + 1].p - samples[i - 1].p).norm() / dt);
  }
  return out;
}

/// Linear interpolation of (t, value) pairs sorted by t; NaN outside.
double interpolate(const std::vector<std::pair<double, double>>& series, double t) {
  const auto it = std::lower_bound(series.begin(), series.end(), t,
                                   [](const std::pair<double, double>& s, double v) { return s.first < v; });
  if (it == series.end() || it == series.begin()) return std::nan("");
  const auto& [t1, v1] = *it;
  const auto& [t0, v0] = *(it - 1);
  return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
}

/// Every XR display frame with its time in the robot clock (through the batch's offset).
struct XrFrameAt {
  link::proto::XrFrame frame;
  double t_robot_s;
  std::int64_t offset_ns;
};

std::vector<XrFrameAt> xrFrames(const LoopRun& run) {
  std::vector<XrFrameAt> frames;
  for (const auto& batch : run.xr) {
    if (!batch.clock_synced()) continue;
    for (const auto& f : batch.frames())
      frames.push_back({f, double(f.display_ns() - batch.robot_to_xr_offset_ns()) * 1e-9, batch.robot_to_xr_offset_ns()});
  }
  std::sort(frames.begin(), frames.end(), [](const auto& a, const auto& b) { return a.t_robot_s < b.t_robot_s; });
  return frames;
}

std::vector<std::pair<double, double>> operatorSpeed(const std::vector<XrFrameAt>& frames) {
  std::vector<TimedPosition> positions;
  for (const auto& f : frames)
    if (f.frame.head_valid()) positions.push_back({f.t_robot_s, link::fromLinkPose(f.frame.t_vr_hmd()).translation()});
  return speeds(positions);
}

std::vector<std::pair<double, double>> robotSpeed(const LoopRun& run) {
  std::vector<TimedPosition> positions;
  std::int64_t last = 0;
  for (const auto& batch : run.robot)
    for (const auto& tick : batch.ticks()) {
      if (tick.joint_state_ns() == 0 || tick.joint_state_ns() == last) continue;
      last = tick.joint_state_ns();
      positions.push_back({double(tick.joint_state_ns()) * 1e-9, link::fromLinkPose(tick.t_robot_head_measured()).translation()});
    }
  std::sort(positions.begin(), positions.end(), [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
  return speeds(positions);
}

double percentile(std::vector<double> v, double q) { return truth::quantile(std::move(v), q); }

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  if (a.size() < 3) return std::nan("");
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n, mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// --- 1. Image latency ------------------------------------------------------------------------

struct ImageLatency {
  std::vector<double> total_ms;
  std::map<std::string, std::vector<double>> stage_ms;  ///< in pipeline order by name prefix
};

ImageLatency imageLatency(const std::vector<XrFrameAt>& frames) {
  ImageLatency out;
  for (const auto& f : frames) {
    if (!f.frame.new_image()) continue;
    const auto& s = f.frame.stamps();
    if (s.capture_ns() == 0 || s.displayed_ns() == 0) continue;
    const auto ms = [](std::int64_t a, std::int64_t b) { return double(b - a) * 1e-6; };
    const std::int64_t off = f.offset_ns;  // robot → XR clock
    out.stage_ms["1 capture → encoded"].push_back(ms(s.capture_ns(), s.encoded_ns()));
    out.stage_ms["2 encoded → sent"].push_back(ms(s.encoded_ns(), s.sent_ns()));
    out.stage_ms["3 sent → received"].push_back(ms(s.sent_ns() + off, s.received_ns()));
    out.stage_ms["4 received → decoded"].push_back(ms(s.received_ns(), s.decoded_ns()));
    out.stage_ms["5 decoded → uploaded"].push_back(ms(s.decoded_ns(), s.uploaded_ns()));
    out.stage_ms["6 uploaded → displayed"].push_back(ms(s.uploaded_ns(), s.displayed_ns()));
    out.total_ms.push_back(ms(s.capture_ns() + off, s.displayed_ns()));
  }
  return out;
}

// --- 2./3. Head latency and Δs ---------------------------------------------------------------

struct HeadResult {
  std::vector<robot::head::HeadMotionSample> trace;
  std::vector<double> t1_ms, t2_ms;  ///< one per move
  std::vector<double> ds_mm, vop_for_ds;  ///< Δs and v_op per display frame during the moves
};

HeadResult headLatency(const LoopRun& run, const std::vector<XrFrameAt>& frames) {
  HeadResult out;
  const auto v_op = operatorSpeed(frames);
  const auto v_rob = robotSpeed(run);
  std::vector<std::pair<double, double>> ds;
  for (const auto& f : frames)
    if (f.frame.eye_camera_distance_m() >= 0) ds.emplace_back(f.t_robot_s, f.frame.eye_camera_distance_m());
  if (v_op.size() < 10 || v_rob.size() < 10) return out;
  const double t_begin = std::max(v_op.front().first, v_rob.front().first);
  const double t_end = std::min(v_op.back().first, v_rob.back().first);
  for (double t = t_begin; t <= t_end; t += 0.005) {
    robot::head::HeadMotionSample s;
    s.t_s = t - t_begin;
    s.v_operator = interpolate(v_op, t);
    s.v_robot = interpolate(v_rob, t);
    s.deviation = ds.empty() ? 0.0 : interpolate(ds, t);
    if (std::isfinite(s.v_operator) && std::isfinite(s.v_robot)) out.trace.push_back(s);
  }
  // One window per operator move: from 0.3 s before it starts to 0.3 s before the next.
  std::vector<double> starts;
  bool moving = false;
  for (const auto& s : out.trace) {
    if (!moving && s.v_operator >= kSpeedThreshold) starts.push_back(s.t_s);
    moving = s.v_operator >= kSpeedThreshold ? true : (s.v_operator < 0.2 * kSpeedThreshold ? false : moving);
  }
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const double a = starts[k] - 0.3, b = k + 1 < starts.size() ? starts[k + 1] - 0.3 : 1e9;
    std::vector<robot::head::HeadMotionSample> window;
    for (const auto& s : out.trace)
      if (s.t_s >= a && s.t_s < b) window.push_back(s);
    const auto latencies = robot::head::measureHeadLatencies(window, kSpeedThreshold);
    if (latencies.start_s) out.t1_ms.push_back(*latencies.start_s * 1e3);
    if (latencies.finish_s) out.t2_ms.push_back(*latencies.finish_s * 1e3);
  }
  if (!starts.empty()) {
    const double first_move = starts.front() + t_begin;
    for (const auto& f : frames) {
      if (f.t_robot_s < first_move || f.frame.eye_camera_distance_m() < 0) continue;
      const double v = interpolate(v_op, f.t_robot_s);
      if (!std::isfinite(v)) continue;
      out.ds_mm.push_back(f.frame.eye_camera_distance_m() * 1e3);
      out.vop_for_ds.push_back(v);
    }
  }
  return out;
}

// --- 5. The eye images against the truth -----------------------------------------------------

struct EyeFrame {
  double v_op;       ///< m/s at its display
  double ds_true_mm;
  double p50_deg, p99_deg;
  std::vector<double> errors;
};

std::vector<EyeFrame> eyeErrors(const LoopRun& run, const std::vector<XrFrameAt>& frames,
                                const calib::SystemCalibration& calibration, std::string* error) {
  std::vector<EyeFrame> out;
  const auto robot_rows = truth::loadRobotTruth(run.robot_truth.string(), error);
  const auto truth_frames = truth::loadXrTruthFrames(run.xr_truth.string(), error);
  if (!robot_rows || !truth_frames) return out;
  const auto v_op = operatorSpeed(frames);
  std::map<std::int64_t, double> t_robot_of_display;
  for (const auto& f : frames) t_robot_of_display[f.frame.display_ns()] = f.t_robot_s;
  const robot::cameras::SyntheticScene scene = robot::cameras::defaultScene();
  for (const auto& frame : *truth_frames) {
    const auto row = robot_rows->find(frame.stereo_sequence);
    const auto t = t_robot_of_display.find(frame.display_ns);
    if (row == robot_rows->end() || t == t_robot_of_display.end() || frame.mode != "full6d") continue;
    const auto map = truth::loadProjectionMap(run.xr_truth.string(), frame, error);
    if (!map) return {};
    std::string why;
    const auto result = truth::evaluateEyeImages(frame, *map, row->second, calibration, scene, {3}, &why);
    if (!result || result->error_deg.empty()) continue;
    const double v = interpolate(v_op, t->second);
    if (!std::isfinite(v)) continue;
    out.push_back({v, result->eye_camera_distance_m * 1e3, truth::quantile(result->error_deg, 0.5),
                   truth::quantile(result->error_deg, 0.99), result->error_deg});
  }
  return out;
}

// --- 4. γ on the renderer --------------------------------------------------------------------

struct GammaPoint {
  double d_m, measured_deg, eq4_deg;
};

/// The eye 10 cm to the side of the camera, looking along its axis, r = 1 m: where a point at d
/// straight ahead of the camera shows in the rendered projection map, against eq. 4.
std::vector<GammaPoint> gammaOnRenderer(const BenchContext& ctx, std::string* error) {
  constexpr double kDx = 0.10, kRadius = 1.0;
  auto context = gl::EglContext::createSurfaceless(error);
  if (!context || !context->makeCurrent()) return {};
  const auto calibration =
      calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  if (!calibration) {
    *error = calibration.error().describe();
    return {};
  }
  const int cw = 1280, ch = 720;
  const auto scaled = calib::atResolution(calibration->cameras[0], cw, ch, error);
  if (!scaled) return {};
  xr::render::GpuCamera gpu(scaled->camera, cw, ch);
  if (!gpu.upload(xr::render::SourceImage::pixelCoordinates(cw, ch), error)) return {};
  xr::render::SphericalRenderer renderer;
  xr::render::RenderSettings settings;
  settings.radius = kRadius;
  settings.border_rgba.setZero();
  xr::render::EyeView view;
  view.width = view.height = ctx.quick ? 400 : 800;
  view.fov = {-0.3, 0.3, 0.3, -0.3};
  view.T_cam_eye = Eigen::Isometry3d(xr::render::kR_optical_view);
  view.T_cam_eye.translation() = Eigen::Vector3d(kDx, 0, 0);
  gl::OffscreenTarget target(view.width, view.height, GL_RGBA32F);
  if (!renderer.render(gpu, view, settings, target.framebuffer(), error)) return {};
  const std::vector<float> map = target.readRgbaF();
  const auto at = [&](int col, int row) {
    const float* v = &map[(static_cast<std::size_t>(row) * view.width + col) * 4];
    return Eigen::Vector2d(v[0], v[1]);
  };
  std::vector<GammaPoint> points;
  for (const double d : {0.3, 0.4, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0, 30.0}) {
    const Eigen::Vector3d p_cam(0, 0, d);
    Eigen::Vector2d target_px;
    if (!scaled->camera.project(p_cam, target_px)) continue;
    // The eye pixel showing that camera pixel: nearest in the map, then one Newton step on the
    // map's local Jacobian (the map is smooth: the renderer's per-pixel projection).
    int best_col = -1, best_row = -1;
    double best = 1e30;
    for (int row = 1; row + 1 < view.height; ++row)
      for (int col = 1; col + 1 < view.width; ++col) {
        const float* v = &map[(static_cast<std::size_t>(row) * view.width + col) * 4];
        if (v[3] < 0.5f) continue;
        const double e = (Eigen::Vector2d(v[0], v[1]) - target_px).squaredNorm();
        if (e < best) best = e, best_col = col, best_row = row;
      }
    if (best_col < 0) continue;
    Eigen::Matrix2d J;
    J.col(0) = 0.5 * (at(best_col + 1, best_row) - at(best_col - 1, best_row));
    J.col(1) = 0.5 * (at(best_col, best_row + 1) - at(best_col, best_row - 1));
    const Eigen::Vector2d step = J.inverse() * (target_px - at(best_col, best_row));
    const Eigen::Vector3d ray_view =
        xr::render::eyeRay(view.fov, view.width, view.height, best_col + step.x(), best_row + step.y()).normalized();
    const Eigen::Vector3d ray_cam = view.T_cam_eye.linear() * ray_view;
    const Eigen::Vector3d truth = (p_cam - view.T_cam_eye.translation()).normalized();
    const double measured = std::atan2(ray_cam.cross(truth).norm(), ray_cam.dot(truth)) * 180.0 / M_PI;
    points.push_back({d, measured, std::abs(xr::render::constantDistanceAngularError(d, kDx, kRadius)) * 180.0 / M_PI});
  }
  return points;
}

// --- The topic -------------------------------------------------------------------------------

template <typename Row>
void writeCsv(const fs::path& path, const std::string& header, const std::vector<Row>& rows,
              const std::function<void(std::ostream&, const Row&)>& line) {
  std::ofstream out(path);
  out.precision(9);
  out << header << '\n';
  for (const Row& r : rows) {
    line(out, r);
    out << '\n';
  }
}

nlohmann::json runExperiments(const BenchContext& ctx) {
  const fs::path out_dir = experimentsOut();
  fs::create_directories(out_dir);
  ensureQtApplication();
  const std::vector<double> radii = ctx.quick ? std::vector<double>{1.0} : std::vector<double>{0.5, 1.0, 3.0};
  const int moves = ctx.quick ? 2 : 4;
  const auto calibration =
      calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  if (!calibration) throw std::runtime_error(calibration.error().describe());

  nlohmann::json json = {{"moves", moves}, {"move_distance_m", kMoveDistance}, {"peak_speed_m_s", kPeakSpeed}};
  std::vector<LoopRun> runs;
  int port = 27900;
  for (const double r : radii) {
    runs.push_back(runLoop(ctx, r, "fixed", moves, port, out_dir / ("run_r" + formatNumber(r))));
    port += 10;
    if (!runs.back().error.empty()) throw std::runtime_error(runs.back().error);
  }
  // The depth proxies from the XR app's own stereo sweep (#35) in the same experiment.
  for (const std::string proxy : {"radius", "grid"}) {
    runs.push_back(runLoop(ctx, 1.0, proxy, moves, port, out_dir / ("run_" + proxy)));
    port += 10;
    if (!runs.back().error.empty()) throw std::runtime_error(runs.back().error);
  }
  // The r = 1 m run (the paper's setting) gives experiments 1–3.
  const auto main_run =
      std::find_if(runs.begin(), runs.end(), [](const LoopRun& r) { return r.radius_m == 1.0 && r.proxy == "fixed"; });
  const auto frames = xrFrames(*main_run);

  // 1. Image latency.
  const ImageLatency latency = imageLatency(frames);
  if (latency.total_ms.empty())
    throw std::runtime_error("no camera frame reached the XR app's display with its stamps (" +
                             (out_dir / "run_r1").string() + ")");
  Table latency_table({"stage", "p50 ms", "p99 ms"});
  nlohmann::json stages;
  for (const auto& [name, values] : latency.stage_ms) {
    latency_table.addRow({name, formatNumber(percentile(values, 0.5)), formatNumber(percentile(values, 0.99))});
    stages[name.substr(2)] = percentile(values, 0.5);
  }
  latency_table.addRow({"capture → displayed", formatNumber(percentile(latency.total_ms, 0.5)),
                        formatNumber(percentile(latency.total_ms, 0.99))});
  ctx.out << "\n1. Image latency, capture (middle of the exposure) → display, " << latency.total_ms.size()
          << " camera frames at 30 Hz, 2×320×180, eyes 2×160×176 at 59 Hz (paper: ≈ 40 ms):\n";
  latency_table.print(ctx.out);
  json["image_latency_p50_ms"] = percentile(latency.total_ms, 0.5);
  json["image_latency_p99_ms"] = percentile(latency.total_ms, 0.99);
  json["image_latency_stage_p50_ms"] = stages;
  {
    std::vector<double> sorted = latency.total_ms;
    std::sort(sorted.begin(), sorted.end());
    FigureSeries cdf{"capture → display", {}, {}, QColor(31, 119, 180)};
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      cdf.x.push_back(sorted[i]);
      cdf.y.push_back(double(i + 1) / double(sorted.size()));
    }
    FigureSeries paper{"paper: 40 ms", {40.0, 40.0}, {0.0, 1.0}, QColor(214, 39, 40)};
    paper.dashed = true;
    writeFigurePng({"Image latency (experiment 1)", "latency capture → display (ms)", "fraction of frames", "",
                    {cdf, paper}},
                   (out_dir / "image_latency.png").string());
    writeCsv<double>(out_dir / "image_latency.csv", "capture_to_display_ms", latency.total_ms,
                     [](std::ostream& o, const double& v) { o << v; });
  }

  // 2./3. Head latency and Δs.
  const HeadResult head = headLatency(*main_run, frames);
  const double t1 = percentile(head.t1_ms, 0.5), t2 = percentile(head.t2_ms, 0.5);
  double ds_mean = 0;
  for (const double d : head.ds_mm) ds_mean += d / double(std::max<std::size_t>(1, head.ds_mm.size()));
  const double ds_corr = pearson(head.ds_mm, head.vop_for_ds);
  Table head_table({"figure", "paper", "here (median of moves)", "moves"});
  head_table.addRow({"start latency t1 ms", "≈ 130", formatNumber(t1), std::to_string(head.t1_ms.size())});
  head_table.addRow({"finish latency t2 ms", "≈ 100", formatNumber(t2), std::to_string(head.t2_ms.size())});
  head_table.addRow({"Δs mean mm (during the moves)", "—", formatNumber(ds_mean), std::to_string(head.ds_mm.size()) + " frames"});
  head_table.addRow({"Δs max mm", "—", formatNumber(percentile(head.ds_mm, 1.0)), ""});
  head_table.addRow({"corr(Δs, v_op)", "Δs follows v_op", formatNumber(ds_corr), ""});
  ctx.out << "\n2./3. Head movement: lateral " << kMoveDistance << " m moves, peak " << kPeakSpeed
          << " m/s (speed threshold " << kSpeedThreshold << " m/s):\n";
  head_table.print(ctx.out);
  json["t1_ms"] = t1;
  json["t2_ms"] = t2;
  json["t1_ms_each"] = head.t1_ms;
  json["t2_ms_each"] = head.t2_ms;
  json["ds_mean_mm"] = ds_mean;
  json["ds_max_mm"] = percentile(head.ds_mm, 1.0);
  json["ds_vop_correlation"] = ds_corr;
  {
    robot::head::writeHeadMotionCsv(out_dir / "head_motion.csv", head.trace);
    const Figure fig6 = headMotionFigure(
        head.trace, "Head speed, operator and robot (experiment 2, paper Fig. 6); t1 " + formatNumber(t1) +
                        " ms, t2 " + formatNumber(t2) + " ms");
    writeFigurePng(fig6, (out_dir / "fig6_head_latency.png").string());
    const FigureSeries& op = fig6.series[0];
    const FigureSeries& ds = fig6.series[2];
    FigureSeries op7{"operator head v_op", op.x, op.y, QColor(31, 119, 180)};
    FigureSeries ds7{"Δs, left eye to left camera at capture (right axis)", ds.x, ds.y, QColor(44, 160, 44)};
    ds7.right_axis = true;
    Figure fig7{"Δs and operator head speed (experiment 3, paper Fig. 7); corr(Δs, v_op) " + formatNumber(ds_corr),
                "time (s)", "operator head speed v_op (m/s)", "Δs (mm)", {op7, ds7}};
    fig7.legend_left = true;
    writeFigurePng(fig7, (out_dir / "fig7_ds_vs_vop.png").string());
  }

  // 4. γ on the renderer.
  std::string error;
  const std::vector<GammaPoint> gamma = gammaOnRenderer(ctx, &error);
  double gamma_err = 0;
  Table gamma_table({"object distance d m", "γ measured deg", "γ eq. 4 deg", "difference deg"});
  for (const auto& g : gamma) {
    gamma_err = std::max(gamma_err, std::abs(g.measured_deg - g.eq4_deg));
    gamma_table.addRow({formatNumber(g.d_m), formatNumber(g.measured_deg, 4), formatNumber(g.eq4_deg, 4),
                        formatNumber(g.measured_deg - g.eq4_deg, 2)});
  }
  ctx.out << "\n4. γ for a 10 cm eye offset at r = 1 m, measured on the GPU renderer's projection map "
          << "(paper Fig. 5, eq. 4)" << (gamma.empty() ? ": " + error : ":") << '\n';
  gamma_table.print(ctx.out);
  json["gamma_max_abs_err_deg"] = gamma.empty() ? nlohmann::json(nullptr) : nlohmann::json(gamma_err);
  {
    FigureSeries measured{"measured on rendered images", {}, {}, QColor(31, 119, 180)}, eq4{"eq. 4", {}, {}, QColor(214, 39, 40)};
    measured.points = true;
    for (const auto& g : gamma) measured.x.push_back(g.d_m), measured.y.push_back(g.measured_deg);
    for (double d = 0.3; d <= 30.0; d *= 1.05)
      eq4.x.push_back(d), eq4.y.push_back(std::abs(xr::render::constantDistanceAngularError(d, 0.1, 1.0)) * 180.0 / M_PI);
    Figure f{"Angular error γ, eye 10 cm off the camera, r = 1 m (experiment 4, paper Fig. 5)", "object distance d (m)",
             "γ (deg)", "", {eq4, measured}};
    f.log_x = true;
    writeFigurePng(f, (out_dir / "fig5_gamma.png").string());
    writeCsv<GammaPoint>(out_dir / "gamma.csv", "d_m,gamma_measured_deg,gamma_eq4_deg", gamma,
                         [](std::ostream& o, const GammaPoint& g) { o << g.d_m << ',' << g.measured_deg << ',' << g.eq4_deg; });
  }

  // 5. The eye images against the truth, per radius and depth proxy, with each run's image latency.
  Table eye_table({"proxy", "frames", "at rest: p50 deg", "p99 deg", "moving (v_op ≥ 0.1 m/s): p50 deg", "p99 deg",
                   "Δs true max mm", "image latency p50 ms"});
  const double fixed_latency_p50_ms = percentile(latency.total_ms, 0.5);
  Figure eye_figure{"Eye-image angular error against the truth (experiment 5)", "operator head speed v_op (m/s)",
                    "error over the eye's pixels, p99 (deg)", "", {}};
  Figure eye_p50_figure{"Eye-image angular error against the truth, median (experiment 5)", "operator head speed v_op (m/s)",
                        "error over the eye's pixels, p50 (deg)", "", {}};
  const QColor colours[] = {QColor(31, 119, 180), QColor(214, 39, 40), QColor(44, 160, 44), QColor(148, 103, 189),
                            QColor(255, 127, 14)};
  nlohmann::json eye_json = nlohmann::json::array();
  std::ofstream eye_csv(out_dir / "eye_error.csv");
  eye_csv << "proxy,radius_m,v_op_m_s,ds_true_mm,error_p50_deg,error_p99_deg\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto run_frames = i == std::size_t(main_run - runs.begin()) ? frames : xrFrames(runs[i]);
    const auto eyes = eyeErrors(runs[i], run_frames, *calibration, &error);
    if (eyes.empty())
      throw std::runtime_error("no recorded frame of the " + runLabel(runs[i]) + " run could be checked against the truth" +
                               (error.empty() ? "" : ": " + error));
    const double latency_p50_ms = percentile(imageLatency(run_frames).total_ms, 0.5);
    std::vector<double> rest, moving;
    double ds_max = 0;
    FigureSeries series{runLabel(runs[i]), {}, {}, colours[i % 5]};
    series.points = true;
    FigureSeries p50_series = series;
    for (const auto& e : eyes) {
      if (e.v_op < kRestSpeed && e.ds_true_mm < kRestDsMm) rest.insert(rest.end(), e.errors.begin(), e.errors.end());
      if (e.v_op >= kMovingSpeed) moving.insert(moving.end(), e.errors.begin(), e.errors.end());
      ds_max = std::max(ds_max, e.ds_true_mm);
      series.x.push_back(e.v_op);
      series.y.push_back(e.p99_deg);
      p50_series.x.push_back(e.v_op);
      p50_series.y.push_back(e.p50_deg);
      eye_csv << runs[i].proxy << ',' << runs[i].radius_m << ',' << e.v_op << ',' << e.ds_true_mm << ',' << e.p50_deg << ',' << e.p99_deg << '\n';
    }
    eye_figure.series.push_back(series);
    eye_p50_figure.series.push_back(p50_series);
    eye_table.addRow({runLabel(runs[i]), std::to_string(eyes.size()), formatNumber(percentile(rest, 0.5), 2),
                      formatNumber(percentile(rest, 0.99), 2), formatNumber(percentile(moving, 0.5), 2),
                      formatNumber(percentile(moving, 0.99), 2), formatNumber(ds_max), formatNumber(latency_p50_ms)});
    if (runs[i].proxy != "fixed") {
      json["eye_error_moving_p50_deg_" + runs[i].proxy] = percentile(moving, 0.5);
      json["eye_error_at_rest_p99_deg_" + runs[i].proxy] = percentile(rest, 0.99);
      json["image_latency_p50_ms_delta_" + runs[i].proxy] = latency_p50_ms - fixed_latency_p50_ms;
    }
    eye_json.push_back({{"proxy", runs[i].proxy}, {"radius_m", runs[i].radius_m}, {"frames", eyes.size()},
                        {"image_latency_p50_ms", latency_p50_ms},
                        {"at_rest_p50_deg", percentile(rest, 0.5)}, {"at_rest_p99_deg", percentile(rest, 0.99)},
                        {"moving_p50_deg", percentile(moving, 0.5)}, {"moving_p99_deg", percentile(moving, 0.99)}});
    if (runs[i].radius_m == 1.0 && runs[i].proxy == "fixed") {
      json["eye_error_at_rest_p99_deg"] = percentile(rest, 0.99);
      json["eye_error_moving_p50_deg"] = percentile(moving, 0.5);
    }
  }
  writeFigurePng(eye_figure, (out_dir / "eye_error.png").string());
  writeFigurePng(eye_p50_figure, (out_dir / "eye_error_p50.png").string());
  json["eye_error"] = eye_json;
  ctx.out << "\n5. What the operator sees against the truth (each eye pixel followed into the known scene; "
             "rest: v_op < " << kRestSpeed << " m/s and Δs < " << kRestDsMm << " mm):\n";
  eye_table.print(ctx.out);

  // The report beside the paper's numbers.
  std::ofstream report(out_dir / "report.md");
  report << "# The paper's experiments, re-run (`telesphere-bench experiments" << (ctx.quick ? " --quick" : "")
         << "`)\n\n| experiment | paper | here |\n|---|---|---|\n"
         << "| 1. image latency capture → display, p50 / p99 | ≈ 40 ms | " << formatNumber(json["image_latency_p50_ms"].get<double>())
         << " / " << formatNumber(json["image_latency_p99_ms"].get<double>()) << " ms |\n"
         << "| 2. head movement start latency t1 | ≈ 130 ms | " << formatNumber(t1) << " ms |\n"
         << "| 2. head movement finish latency t2 | ≈ 100 ms | " << formatNumber(t2) << " ms |\n"
         << "| 3. Δs during fast motion, mean / max | Fig. 7 | " << formatNumber(ds_mean) << " / "
         << formatNumber(percentile(head.ds_mm, 1.0)) << " mm, corr(Δs, v_op) " << formatNumber(ds_corr) << " |\n"
         << "| 4. γ measured on rendered images vs eq. 4, max difference | Fig. 5 | " << formatNumber(gamma_err, 2)
         << " deg |\n"
         << "| 5. eye-image error at rest, p99 (r = 1 m) | — | " << formatNumber(json.value("eye_error_at_rest_p99_deg", 0.0), 2)
         << " deg |\n"
         << "| 5. eye-image error moving (≥ 0.1 m/s), p50 (r = 1 m) | — | "
         << formatNumber(json.value("eye_error_moving_p50_deg", 0.0), 2) << " deg |\n"
         << "| 5. the same, moving p50, one radius / grid from the XR app's stereo sweep (#35) | — | "
         << formatNumber(json.value("eye_error_moving_p50_deg_radius", 0.0), 2) << " / "
         << formatNumber(json.value("eye_error_moving_p50_deg_grid", 0.0), 2) << " deg |\n"
         << "| 5. image latency p50 with them, against the fixed sphere | — | "
         << formatNumber(json.value("image_latency_p50_ms_delta_radius", 0.0)) << " / "
         << formatNumber(json.value("image_latency_p50_ms_delta_grid", 0.0)) << " ms |\n\n"
         << "Figures: image_latency.png, fig6_head_latency.png, fig7_ds_vs_vop.png, fig5_gamma.png, eye_error.png, eye_error_p50.png; "
            "data: the CSV files beside them.\n";
  ctx.out << "\nwritten to " << out_dir.string() << " (report.md, figures, CSV)\n";
  return json;
}

}  // namespace

TELESPHERE_BENCH_TOPIC(experiments,
                       BenchTopic{"experiments",
                                  "the paper's experiments end to end (robot + XR app on loopback) against the truth",
                                  [](CLI::App& sub) {
                                    sub.add_option("--out", experimentsOut(), "folder for CSV, figures and report.md")
                                        ->capture_default_str();
                                  },
                                  runExperiments});

}  // namespace telesphere::bench
