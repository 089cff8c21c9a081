// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench network`: the Internet link measured end to end (DESIGN.md §9). Real
///        telesphere-robot and telesphere-xr (offscreen) processes through an impaired path
///        (app/bench/impairment: one-way delay and jitter, Bernoulli or burst loss, a rate with a
///        drop-tail queue, rate steps), both directions, twice with the same seeds: the media path
///        (`--video-link udp --head-link udp`) and, as the baseline, today's ZeroMQ/TCP link
///        (`--video-link zmq`, the robot with `--no-media`).
///
///        With CAP_NET_ADMIN (root) the path acts on IP packets (TunRelay): the benchmark's own
///        network namespace holds the robot, the XR app runs in the relay's far namespace and
///        reaches the robot at 10.77.0.1, so everything between them — TCP with its kernel's
///        retransmissions and CUBIC (pinned; these machines default to BBR), UDP, the control
///        link — crosses the same relay. Without it, only the media path is measured, through the
///        UDP relay on loopback (the ZeroMQ link beside it unimpaired), and the baseline says why not.
///        The figures come from the relay's per-packet log and from the telemetry both programs
///        send (every displayed frame's capture and display stamps, every sent frame), which the
///        benchmark takes from the robot on loopback.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <mutex>
#include <set>
#include <thread>

#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/child_process.h"
#include "app/bench/impairment/bulk_tcp_flow.h"
#include "app/bench/impairment/network_namespace.h"
#include "app/bench/impairment/tun_relay.h"
#include "app/bench/impairment/udp_relay.h"
#include "robot/link/link_client.h"
#include "robot/link/media/media_packet.h"

namespace telesphere::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using impairment::PathOptions;
using impairment::RateTrace;

struct NetworkOptions {
  double rtt_ms = 100;
  double jitter_ms = 10;  ///< ± on the round trip (± half of it each way)
  double loss = 0.01;
  double loss_burst = 1;
  double rate_mbit = 50;
  std::string rate_steps;  ///< "T:M,…"
  double duration_s = 20;
  std::string size = "960x540";
  double fps = 30;
  std::string out = "bench-out/network";
  bool udp_relay_only = false;  ///< the media path through the UDP relay only, even with the privilege
  bool competing_tcp = false;   ///< a bulk TCP download beside the robot's video (relay on IP packets)
  bool media_repair = true;     ///< the media path asks for what parity cannot rebuild
  std::string codec = "mjpeg";  ///< the robot's --codec (#34): both links carry it
};

NetworkOptions& networkOptions() {
  static NetworkOptions o;
  return o;
}

/// A packet as it left the relay's client-bound path.
struct Delivered {
  std::int64_t offered_ns, left_bottleneck_ns, arrives_ns;  ///< relay clock
  std::size_t bytes;
};

struct DisplayedFrame {
  double t_s;            ///< display time, s after the XR app's first telemetry frame (XR clock)
  double age_ms;         ///< display − capture
  std::uint64_t sequence;
  bool new_image;
  double robot_ms, network_ms, operator_ms;  ///< capture → sent, sent → received, received → displayed
};

double quantileOr(std::vector<double> v, double q) { return v.empty() ? std::nan("") : quantile(std::move(v), q); }

nlohmann::json numberOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

enum class Path { kUdpRelay, kTunRelay };
enum class Link { kMedia, kBaseline };

/// One run's figures: the keys and more, the table row, and a line of detail.
struct Measured {
  nlohmann::json keys;
  std::vector<std::string> row;
  std::string detail;
};

PathOptions pathOptions(const NetworkOptions& o, bool downlink, const RateTrace& trace) {
  PathOptions path;
  path.one_way_delay_ns = static_cast<std::int64_t>(o.rtt_ms * 0.5e6);
  path.jitter_ns = static_cast<std::int64_t>(o.jitter_ms * 0.25e6);
  path.loss.loss_fraction = o.loss;
  path.loss.mean_burst_packets = o.loss_burst;
  path.loss.seed = downlink ? 5 : 6;
  if (downlink) path.rate = trace;
  return path;
}

/// Runs robot and XR app for `duration` through the path and measures. Called on a thread in the
/// benchmark's private network namespace for kTunRelay.
Measured measureRun(const NetworkOptions& o, double duration, const RateTrace& trace, const fs::path& dir, Path path_kind,
                    Link link_kind) {
  fs::create_directories(dir);
  const fs::path bin = fs::read_symlink("/proc/self/exe").parent_path();
  const std::string calib = std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml";
  const int port = 28100;
  const bool media = link_kind == Link::kMedia;
  std::string error;

  std::vector<std::string> robot_args{(bin / "telesphere-robot").string(), "--insecure", "--sim", "--size", o.size, "--fps",
                                      formatNumber(o.fps), "--port", std::to_string(port), "--duration", "600",
                                      "--stats-period", "2", "--render-threads", "1", "--preview-rate", "0"};
  if (!media) robot_args.push_back("--no-media");
  robot_args.insert(robot_args.end(), {"--codec", o.codec});
  ChildProcess robot(robot_args, (dir / "robot.log").string());
  if (!robot.running()) throw std::runtime_error("network: cannot start " + robot_args[0]);

  // Packets as they leave the downlink (towards the operator), relay clock.
  std::mutex delivered_mutex;
  std::vector<Delivered> delivered;
  const auto log = [&](const impairment::PathPacket& p, bool downlink) {
    if (!downlink) return;
    std::lock_guard lock(delivered_mutex);
    delivered.push_back({p.offered_ns, p.left_bottleneck_ns, p.arrives_ns, p.bytes.size()});
  };
  std::unique_ptr<impairment::UdpRelay> udp_relay;
  std::unique_ptr<impairment::TunRelay> tun_relay;
  std::vector<std::string> xr_args{(bin / "telesphere-xr").string(), "offscreen", "--insecure", "--calib", calib, "--port",
                                   std::to_string(port), "--eye-size", "320x352", "--rate", "60", "--duration",
                                   formatNumber(duration), "--out", (dir / "xr").string(), "--wait", "60"};
  if (media)
    xr_args.insert(xr_args.end(), {"--video-link", "udp", "--head-link", "udp", "--media-repair", o.media_repair ? "on" : "off"});
  if (path_kind == Path::kUdpRelay) {
    impairment::UdpRelayOptions options;
    options.server_port = static_cast<std::uint16_t>(port + link::LinkEndpoints::kMedia);
    options.to_client = pathOptions(o, true, trace);
    options.to_server = pathOptions(o, false, trace);
    options.on_arrival = log;
    udp_relay = impairment::UdpRelay::start(options, &error);
    if (!udp_relay) throw std::runtime_error("network: relay: " + error);
    xr_args.insert(xr_args.end(), {"--media-port", std::to_string(udp_relay->port())});
  } else {
    impairment::TunRelayOptions options;
    options.to_far = pathOptions(o, true, trace);
    options.to_near = pathOptions(o, false, trace);
    options.on_arrival = log;
    tun_relay = impairment::TunRelay::start(options, &error);
    if (!tun_relay) throw std::runtime_error("network: relay on IP packets: " + error);
    xr_args.insert(xr_args.end(), {"--host", impairment::TunRelay::kNearAddress});
  }

  link::LinkEndpoints endpoints;
  endpoints.base_port = port;
  link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false, .telemetry = true});
  std::unique_ptr<ChildProcess> xr;
  if (tun_relay) {
    if (!impairment::runInNetworkNamespace(tun_relay->farNamespace(),
                                           [&] { xr = std::make_unique<ChildProcess>(xr_args, (dir / "xr.log").string()); },
                                           &error))
      throw std::runtime_error("network: the XR app's namespace: " + error);
  } else {
    xr = std::make_unique<ChildProcess>(xr_args, (dir / "xr.log").string());
  }
  // A download beside the video, through the same bottleneck, for the whole run.
  std::unique_ptr<impairment::BulkTcpFlow> competing;
  const auto competing_from = Clock::now();
  if (o.competing_tcp) {
    if (!tun_relay) throw std::runtime_error("network: --competing-tcp needs the relay on IP packets (CAP_NET_ADMIN)");
    competing = impairment::BulkTcpFlow::start(tun_relay->farNamespace(), impairment::TunRelay::kFarAddress, 29500, &error);
    if (!competing) throw std::runtime_error("network: " + error);
  }
  std::vector<link::proto::XrTelemetry> xr_batches;
  std::vector<link::proto::RobotTelemetry> robot_batches;
  const auto take = [&] {
    for (auto& envelope : client.takeTelemetry()) {
      if (envelope.has_xr_telemetry()) xr_batches.push_back(std::move(*envelope.mutable_xr_telemetry()));
      if (envelope.has_robot_telemetry()) robot_batches.push_back(std::move(*envelope.mutable_robot_telemetry()));
    }
  };
  const auto deadline = Clock::now() + std::chrono::duration<double>(duration + 90.0);
  std::optional<int> xr_code;
  while (!(xr_code = xr->wait(std::chrono::milliseconds(20))) && Clock::now() < deadline) take();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  take();
  const int robot_code = robot.stop();
  const double competing_mbit =
      competing ? 8.0 * static_cast<double>(competing->bytesReceived()) /
                      std::chrono::duration<double>(Clock::now() - competing_from).count() * 1e-6
                : 0.0;
  competing.reset();
  impairment::PathStats downlink;
  if (udp_relay) downlink = udp_relay->stats().to_client;
  if (tun_relay) downlink = tun_relay->stats().to_far;
  udp_relay.reset();
  tun_relay.reset();
  if (!xr_code || *xr_code != 0)
    throw std::runtime_error("network: telesphere-xr offscreen " +
                             (xr_code ? "exited with " + std::to_string(*xr_code) : std::string("did not finish")) + " (" +
                             (dir / "xr.log").string() + ")");
  if (robot_code != 0)
    throw std::runtime_error("network: telesphere-robot exited with " + std::to_string(robot_code) + " (" +
                             (dir / "robot.log").string() + ")");
  nlohmann::json xr_stats;
  std::ifstream(dir / "xr" / "stats.json") >> xr_stats;

  // Displayed frames, from the XR app's telemetry (capture in the robot clock, display in the XR clock).
  std::vector<DisplayedFrame> shown;
  std::optional<std::int64_t> xr_t0;
  for (const auto& batch : xr_batches) {
    if (!batch.clock_synced()) continue;
    for (const auto& f : batch.frames()) {
      if (f.stereo_sequence() == 0 || f.stamps().capture_ns() == 0) continue;
      if (!xr_t0) xr_t0 = f.display_ns();
      const double age = static_cast<double>(f.display_ns() - (f.stamps().capture_ns() + batch.robot_to_xr_offset_ns())) * 1e-6;
      const auto& st = f.stamps();
      const std::int64_t offset = batch.robot_to_xr_offset_ns();
      shown.push_back({static_cast<double>(f.display_ns() - *xr_t0) * 1e-9, age, f.stereo_sequence(), f.new_image(),
                       static_cast<double>(st.sent_ns() - st.capture_ns()) * 1e-6,
                       static_cast<double>(st.received_ns() - (st.sent_ns() + offset)) * 1e-6,
                       static_cast<double>(f.display_ns() - st.received_ns()) * 1e-6});
    }
  }
  std::uint64_t frames_sent = 0;
  std::map<std::uint64_t, std::uint32_t> jpeg_bytes_of;  // sequence → both JPEGs' bytes
  for (const auto& batch : robot_batches)
    for (const auto& f : batch.frames()) {
      ++frames_sent;
      jpeg_bytes_of[f.sequence()] = f.jpeg_bytes();
    }
  if (shown.empty() || frames_sent == 0) throw std::runtime_error("network: no frame reached the display (" + dir.string() + ")");

  const double warmup_s = std::min(3.0, duration / 3);
  std::vector<double> g2g, robot_ms, network_ms, operator_ms;
  std::set<std::uint64_t> sequences, sequences_after_warmup;
  double max_age = 0;
  for (const DisplayedFrame& f : shown) {
    sequences.insert(f.sequence);
    if (f.t_s < warmup_s) continue;
    sequences_after_warmup.insert(f.sequence);
    max_age = std::max(max_age, f.age_ms);
    if (!f.new_image) continue;
    g2g.push_back(f.age_ms);
    robot_ms.push_back(f.robot_ms);
    network_ms.push_back(f.network_ms);
    operator_ms.push_back(f.operator_ms);
  }
  // Head targets at the robot: when sampled (robot clock, through the XR app's offset) to when the
  // head loop took them, for every tick that acted on a new one; the first 3 s (300 ticks) skipped.
  std::vector<double> pose_age_ms;
  for (const auto& batch : robot_batches)
    for (const auto& tick : batch.ticks())
      if (tick.target_new() && tick.target_t_ns() > 0 && tick.target_arrival_ns() > tick.target_t_ns())
        pose_age_ms.push_back(static_cast<double>(tick.target_arrival_ns() - tick.target_t_ns()) * 1e-6);
  if (pose_age_ms.size() > 300) pose_age_ms.erase(pose_age_ms.begin(), pose_age_ms.begin() + 300);
  const double late_limit_ms = o.rtt_ms / 2 + 100.0;
  const double pose_late = pose_age_ms.empty()
                               ? std::nan("")
                               : static_cast<double>(std::count_if(pose_age_ms.begin(), pose_age_ms.end(),
                                                                   [&](double a) { return a > late_limit_ms; })) /
                                     static_cast<double>(pose_age_ms.size());
  std::uint64_t jpeg_bytes = 0;
  std::int64_t sent_first_ns = 0, sent_last_ns = 0;
  for (const auto& batch : robot_batches)
    for (const auto& f : batch.frames()) {
      jpeg_bytes += f.jpeg_bytes();
      if (sent_first_ns == 0) sent_first_ns = f.sent_ns();
      sent_last_ns = f.sent_ns();
    }
  const double source_mbit =
      sent_last_ns > sent_first_ns ? 8.0 * static_cast<double>(jpeg_bytes) / (static_cast<double>(sent_last_ns - sent_first_ns) * 1e-9) * 1e-6 : 0;
  std::vector<double> queue_ms;
  std::int64_t first_ns = 0, last_ns = 0;
  {
    std::lock_guard lock(delivered_mutex);
    if (!delivered.empty()) first_ns = delivered.front().arrives_ns;
    for (const Delivered& d : delivered) {
      if (static_cast<double>(d.arrives_ns - first_ns) * 1e-9 < warmup_s) continue;
      queue_ms.push_back(static_cast<double>(d.left_bottleneck_ns - d.offered_ns) * 1e-6);
      last_ns = d.arrives_ns;
    }
  }
  // Goodput: the video that reached the display (both JPEGs of every frame shown after the
  // warm-up) over the path's capacity in the same span (the relay's clock: the rate trace counts
  // from its start).
  double video_bits = 0;
  for (const std::uint64_t sequence : sequences_after_warmup)
    if (const auto it = jpeg_bytes_of.find(sequence); it != jpeg_bytes_of.end()) video_bits += 8.0 * it->second;
  double capacity_bits = 0;
  const std::int64_t from_ns = first_ns + static_cast<std::int64_t>(warmup_s * 1e9);
  for (std::int64_t t = from_ns; t < last_ns; t += 10'000'000) capacity_bits += trace.bitsPerSecondAt(t) * 0.01;
  const double goodput = capacity_bits > 0 ? video_bits / capacity_bits : std::nan("");

  // Recovery after each rate step (relay clock → seconds after the step).
  nlohmann::json steps = nlohmann::json::array();
  {
    std::vector<std::pair<double, double>> parsed;  // (t s, Mbit/s), the step at 0 s left out
    for (const impairment::RateStep& step : trace.rateSteps())
      if (step.from_ns > 0) parsed.emplace_back(static_cast<double>(step.from_ns) * 1e-9, step.bits_per_s * 1e-6);
    double previous_mbit = o.rate_mbit;
    std::lock_guard lock(delivered_mutex);
    for (const auto& [t_s, mbit] : parsed) {
      const std::int64_t step_ns = static_cast<std::int64_t>(t_s * 1e9);
      nlohmann::json step = {{"t_s", t_s}, {"from_mbit", previous_mbit}, {"to_mbit", mbit}};
      if (mbit < previous_mbit) {
        // Until every packet's queuing stays below 200 ms − one-way delay (glass-to-glass under 200 ms
        // needs at least that), measured at the relay.
        const double limit_ms = 200.0 - o.rtt_ms / 2;
        std::optional<std::int64_t> last_bad;
        for (const Delivered& d : delivered)
          if (d.offered_ns >= step_ns && static_cast<double>(d.left_bottleneck_ns - d.offered_ns) * 1e-6 >= limit_ms)
            last_bad = d.offered_ns;
        step["recover_down_s"] = last_bad ? static_cast<double>(*last_bad - step_ns) * 1e-9 : 0.0;
      } else {
        // Until 250 ms of delivered packets reach 80 % of the new capacity.
        std::optional<double> reached;
        for (std::size_t i = 0; i < delivered.size() && !reached; ++i) {
          if (delivered[i].arrives_ns < step_ns) continue;
          double bytes = 0;
          std::size_t j = i;
          for (; j < delivered.size() && delivered[j].arrives_ns < delivered[i].arrives_ns + 250'000'000; ++j)
            bytes += static_cast<double>(delivered[j].bytes);
          if (j < delivered.size() && 8.0 * bytes / 0.25 >= 0.8 * mbit * 1e6)
            reached = static_cast<double>(delivered[i].arrives_ns - step_ns) * 1e-9;
        }
        step["recover_up_s"] = reached ? nlohmann::json(*reached) : nlohmann::json(nullptr);
      }
      steps.push_back(step);
      previous_mbit = mbit;
    }
  }

  // Over TCP every frame shown is whole; on the media path, the ones without a filled band.
  const double shown_fraction = static_cast<double>(sequences.size()) / static_cast<double>(frames_sent);
  const double complete_fraction =
      media ? xr_stats.value("media_frames_whole", 0.0) / static_cast<double>(frames_sent) : shown_fraction;
  Measured m;
  m.keys = {{"measured", true},
            {"path", path_kind == Path::kTunRelay ? "IP packets (TUN), both links" : "UDP datagrams (media path only)"},
            {"goodput_fraction", numberOrNull(goodput)},
            {"glass_to_glass_p50_ms", numberOrNull(quantileOr(g2g, 0.5))},
            {"glass_to_glass_p99_ms", numberOrNull(quantileOr(g2g, 0.99))},
            {"added_queuing_p95_ms", numberOrNull(quantileOr(queue_ms, 0.95))},
            {"frames_complete_fraction", complete_fraction},
            {"frames_shown_fraction", shown_fraction},
            {"max_shown_age_ms", max_age},
            {"pose_age_p99_ms", numberOrNull(quantileOr(pose_age_ms, 0.99))},
            {"pose_age_p50_ms", numberOrNull(quantileOr(pose_age_ms, 0.5))},
            {"pose_late_fraction", numberOrNull(pose_late)},
            {"pose_targets", pose_age_ms.size()},
            {"frames_sent", frames_sent},
            {"source_mbit", source_mbit},
            {"robot_ms_p50", numberOrNull(quantileOr(robot_ms, 0.5))},
            {"network_ms_p50", numberOrNull(quantileOr(network_ms, 0.5))},
            {"operator_ms_p50", numberOrNull(quantileOr(operator_ms, 0.5))},
            {"relay_lost", downlink.lost},
            {"relay_dropped_at_queue", downlink.dropped_queue},
            {"rate_steps", steps}};
  if (o.competing_tcp) m.keys["competing_tcp_mbit"] = competing_mbit;
  if (media) {
    m.keys["frames_with_lost_bands"] = xr_stats.value("media_frames_concealed", 0);
    m.keys["frames_lost"] = xr_stats.value("media_frames_lost", 0);
    m.keys["bands_lost"] = xr_stats.value("media_bands_lost", 0);
    m.keys["rows_painted_from_previous"] = xr_stats.value("rows_concealed", 0);
    m.keys["frames_superseded"] = xr_stats.value("media_frames_superseded", 0);
    m.keys["chunks_rebuilt_from_parity"] = xr_stats.value("media_chunks_fec", 0);
    m.keys["chunks_requested"] = xr_stats.value("media_chunks_requested", 0);
    m.keys["chunks_repaired"] = xr_stats.value("media_chunks_repaired", 0);
    m.keys["repair"] = o.media_repair;
  }
  // The keys: the first step down's and the first step up's recovery (null: no such step,
  // or not reached).
  m.keys["recover_down_s"] = nullptr;
  m.keys["recover_up_s"] = nullptr;
  for (const auto& step : steps) {
    if (step.contains("recover_down_s") && m.keys["recover_down_s"].is_null()) m.keys["recover_down_s"] = step["recover_down_s"];
    if (step.contains("recover_up_s") && m.keys["recover_up_s"].is_null()) m.keys["recover_up_s"] = step["recover_up_s"];
  }
  const auto stepText = [&](const char* key) {
    for (const auto& step : steps)
      if (step.contains(key)) return step[key].is_null() ? std::string("not reached") : formatNumber(step[key].get<double>());
    return std::string("-");
  };
  m.row = {media ? "media path (UDP)" : "ZeroMQ/TCP (baseline)", formatNumber(goodput), formatNumber(quantileOr(g2g, 0.5)),
           formatNumber(quantileOr(g2g, 0.99)), formatNumber(quantileOr(queue_ms, 0.95)), formatNumber(complete_fraction),
           formatNumber(shown_fraction), formatNumber(max_age), formatNumber(quantileOr(pose_age_ms, 0.99)),
           formatNumber(pose_late), stepText("recover_down_s"), stepText("recover_up_s")};
  std::ostringstream detail;
  detail << m.row[0] << ": capture → sent " << formatNumber(quantileOr(robot_ms, 0.5)) << " ms p50 (robot), sent → received "
         << formatNumber(quantileOr(network_ms, 0.5)) << " ms (path), received → displayed "
         << formatNumber(quantileOr(operator_ms, 0.5)) << " ms (operator); " << formatNumber(source_mbit)
         << " Mbit/s of " << (o.codec == "mjpeg" ? "JPEG" : o.codec) << " sent in " << frames_sent << " frames";
  if (media)
    detail << ", " << xr_stats.value("media_frames_concealed", 0) << " with lost bands, " << xr_stats.value("media_frames_lost", 0)
           << " lost, " << xr_stats.value("media_frames_superseded", 0) << " superseded incomplete; chunks rebuilt from parity "
           << xr_stats.value("media_chunks_fec", 0) << ", asked for again " << xr_stats.value("media_chunks_requested", 0)
           << ", repaired in time " << xr_stats.value("media_chunks_repaired", 0);
  if (o.competing_tcp) detail << "; the competing TCP download got " << formatNumber(competing_mbit) << " Mbit/s";
  detail << "; relay: " << downlink.lost << " lost, " << downlink.dropped_queue << " dropped at its queue\n";
  m.detail = detail.str();
  return m;
}

nlohmann::json runNetwork(const BenchContext& ctx) {
  const NetworkOptions& o = networkOptions();
  const double duration = ctx.quick ? std::min(o.duration_s, 8.0) : o.duration_s;
  std::string error;
  std::optional<RateTrace> trace = o.rate_steps.empty() ? RateTrace::constant(o.rate_mbit * 1e6)
                                                        : RateTrace::parseSteps(o.rate_mbit * 1e6, o.rate_steps, &error);
  if (!trace) throw std::runtime_error("network: --rate-steps: " + error);
  const fs::path dir = o.out;
  fs::create_directories(dir);

  ctx.out << "network: " << o.size << " stereo at " << formatNumber(o.fps) << " Hz, RTT " << formatNumber(o.rtt_ms)
          << " ± " << formatNumber(o.jitter_ms / 2) << " ms each way, loss " << formatNumber(100 * o.loss) << " %"
          << (o.loss_burst > 1 ? " in bursts of " + formatNumber(o.loss_burst) : std::string()) << ", "
          << (o.rate_steps.empty() ? formatNumber(o.rate_mbit) + " Mbit/s" : formatNumber(o.rate_mbit) + " Mbit/s then " + o.rate_steps)
          << (o.competing_tcp ? ", beside a bulk TCP download" : "") << ", " << formatNumber(duration)
          << " s each link…\n" << std::flush;

  // Both links through IP packets, in a network namespace of the benchmark's own (a thread of
  // its own enters it; what it starts stays there). Without the privilege: the media path only.
  std::optional<Measured> media, baseline;
  std::string baseline_why;
  std::exception_ptr failure;
  std::thread([&] {
    std::string why;
    if (!o.udp_relay_only && impairment::enterPrivateNetworkNamespace(&why)) {
      try {
        media = measureRun(o, duration, *trace, dir / "media", Path::kTunRelay, Link::kMedia);
        baseline = measureRun(o, duration, *trace, dir / "baseline", Path::kTunRelay, Link::kBaseline);
      } catch (...) {
        failure = std::current_exception();
      }
      return;
    }
    baseline_why = o.udp_relay_only ? "--udp-relay-only" : "TCP through the same path needs a relay on IP packets, and " + why;
    try {
      media = measureRun(o, duration, *trace, dir / "media", Path::kUdpRelay, Link::kMedia);
    } catch (...) {
      failure = std::current_exception();
    }
  }).join();
  if (failure) std::rethrow_exception(failure);

  Table table({"link", "goodput", "g2g p50 ms", "g2g p99 ms", "queue p95 ms", "complete", "shown", "max age ms",
               "pose p99 ms", "pose late", "recover down s", "recover up s"});
  table.addRow(media->row);
  if (baseline)
    table.addRow(baseline->row);
  else
    table.addRow({"ZeroMQ/TCP (baseline)", "not measured", "-", "-", "-", "-", "-", "-", "-", "-", "-", "-"});
  table.print(ctx.out);
  ctx.out << media->detail << (baseline ? baseline->detail : "baseline not measured: " + baseline_why + "\n")
          << "path: " << media->keys["path"].get<std::string>()
          << (baseline ? "; TCP congestion control CUBIC, pinned on both routes" : "") << "\n"
          << "codec " << o.codec << "; goodput = video shown (both images of every frame displayed) / capacity; head targets on the media path\n"
          << "only (--head-link udp), on TCP for the baseline; pose late = older than one-way + 100 ms\n"
          << "logs: " << dir.string() << "\n";

  nlohmann::json baseline_keys =
      baseline ? baseline->keys : nlohmann::json{{"measured", false}, {"why", baseline_why}};
  return {{"rtt_ms", o.rtt_ms},         {"jitter_ms", o.jitter_ms}, {"loss", o.loss},
          {"loss_burst", o.loss_burst}, {"rate_mbit", o.rate_mbit}, {"rate_steps", o.rate_steps},
          {"duration_s", duration},     {"size", o.size},           {"fps", o.fps},
          {"codec", o.codec},
          {"media", media->keys},       {"baseline", baseline_keys}};
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(network, telesphere::bench::BenchTopic{
    "network",
    "the Internet link end to end: robot and XR app through an impaired path (delay, jitter, loss, rate steps)",
    [](CLI::App& sub) {
      auto& o = telesphere::bench::networkOptions();
      sub.add_option("--rtt-ms", o.rtt_ms, "round-trip time, ms")->capture_default_str()->check(CLI::Range(0.0, 2000.0));
      sub.add_option("--jitter-ms", o.jitter_ms, "jitter on the round trip, ± ms")->capture_default_str()->check(CLI::Range(0.0, 500.0));
      sub.add_option("--loss", o.loss, "loss fraction each way")->capture_default_str()->check(CLI::Range(0.0, 0.5));
      sub.add_option("--loss-burst", o.loss_burst, "mean burst length, packets (1: independent)")
          ->capture_default_str()->check(CLI::Range(1.0, 1000.0));
      sub.add_option("--rate-mbit", o.rate_mbit, "bottleneck rate, Mbit/s")->capture_default_str()->check(CLI::Range(0.1, 10000.0));
      sub.add_option("--rate-steps", o.rate_steps, "later rates: \"T:M,T:M,…\" (s from the start : Mbit/s)");
      sub.add_option("--duration", o.duration_s, "seconds of video")->capture_default_str()->check(CLI::Range(4.0, 3600.0));
      sub.add_option("--size", o.size, "camera size WxH (synthetic cameras)")->capture_default_str();
      sub.add_option("--fps", o.fps, "camera rate, Hz")->capture_default_str()->check(CLI::Range(1.0, 120.0));
      sub.add_option("--out", o.out, "folder for the programs' logs and stats")->capture_default_str();
      sub.add_option("--codec", o.codec, "the robot's video codec (mjpeg, h264, hevc)")
          ->capture_default_str()->check(CLI::IsMember({"mjpeg", "h264", "hevc"}));
      sub.add_flag("--media-repair,!--no-media-repair", o.media_repair,
                   "the media path asks again for chunks its parity cannot rebuild (default on)");
      sub.add_flag("--competing-tcp", o.competing_tcp,
                   "a bulk TCP download (CUBIC) through the same bottleneck beside the video, each run");
      sub.add_flag("--udp-relay-only", o.udp_relay_only,
                   "the media path alone through the UDP relay on loopback (no baseline; what runs without "
                   "CAP_NET_ADMIN)");
    },
    telesphere::bench::runNetwork});
