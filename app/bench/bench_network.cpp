// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench network`: the Internet link measured end to end (DESIGN.md §9). Real
///        telesphere-robot and telesphere-xr (offscreen, --video-link udp) processes; the media
///        path runs through the impairment relay (app/bench/impairment: one-way delay and jitter,
///        Bernoulli or burst loss, a rate with a drop-tail queue, rate steps), in both directions.
///        The figures come from the relay's per-packet log and from the telemetry both programs
///        send on the (unimpaired) ZeroMQ link: every displayed frame's capture and display stamps,
///        every sent frame.
///
///        Head targets go on the media path only (`--head-link udp`), through the relay too.
///        Not yet measured here, and said so in the output: today's ZeroMQ/TCP link through the
///        same path (`baseline`: it needs a relay that acts on IP packets, a TUN pair in a network
///        namespace).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>

#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/child_process.h"
#include "app/bench/impairment/udp_relay.h"
#include "robot/link/link_client.h"
#include "robot/link/media/media_packet.h"

namespace telesphere::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
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

nlohmann::json runNetwork(const BenchContext& ctx) {
  const NetworkOptions& o = networkOptions();
  const double duration = ctx.quick ? std::min(o.duration_s, 8.0) : o.duration_s;
  std::string error;
  std::optional<RateTrace> trace = o.rate_steps.empty() ? RateTrace::constant(o.rate_mbit * 1e6)
                                                        : RateTrace::parseSteps(o.rate_mbit * 1e6, o.rate_steps, &error);
  if (!trace) throw std::runtime_error("network: --rate-steps: " + error);
  const fs::path dir = o.out;
  fs::create_directories(dir);
  const fs::path bin = fs::read_symlink("/proc/self/exe").parent_path();
  const std::string calib = std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml";
  const int port = 28100;

  ctx.out << "network: " << o.size << " stereo at " << formatNumber(o.fps) << " Hz, RTT " << formatNumber(o.rtt_ms)
          << " ± " << formatNumber(o.jitter_ms / 2) << " ms each way, loss " << formatNumber(100 * o.loss) << " %"
          << (o.loss_burst > 1 ? " in bursts of " + formatNumber(o.loss_burst) : std::string()) << ", "
          << (o.rate_steps.empty() ? formatNumber(o.rate_mbit) + " Mbit/s" : formatNumber(o.rate_mbit) + " Mbit/s then " + o.rate_steps)
          << ", " << formatNumber(duration) << " s…\n" << std::flush;

  ChildProcess robot({(bin / "telesphere-robot").string(), "--sim", "--size", o.size, "--fps", formatNumber(o.fps),
                      "--port", std::to_string(port), "--duration", "600", "--stats-period", "2", "--render-threads", "1",
                      "--preview-rate", "0"},
                     (dir / "robot.log").string());
  if (!robot.running()) throw std::runtime_error("network: cannot start " + (bin / "telesphere-robot").string());

  impairment::UdpRelayOptions relay_options;
  relay_options.server_port = static_cast<std::uint16_t>(port + link::LinkEndpoints::kMedia);
  for (auto* path : {&relay_options.to_client, &relay_options.to_server}) {
    path->one_way_delay_ns = static_cast<std::int64_t>(o.rtt_ms * 0.5e6);
    path->jitter_ns = static_cast<std::int64_t>(o.jitter_ms * 0.25e6);
    path->loss.loss_fraction = o.loss;
    path->loss.mean_burst_packets = o.loss_burst;
  }
  relay_options.to_client.loss.seed = 5;
  relay_options.to_server.loss.seed = 6;
  relay_options.to_client.rate = *trace;
  std::mutex delivered_mutex;
  std::vector<Delivered> delivered;
  relay_options.on_arrival = [&](const impairment::PathPacket& p, bool to_client) {
    if (!to_client) return;
    std::lock_guard lock(delivered_mutex);
    delivered.push_back({p.offered_ns, p.left_bottleneck_ns, p.arrives_ns, p.bytes.size()});
  };
  auto relay = impairment::UdpRelay::start(relay_options, &error);
  if (!relay) throw std::runtime_error("network: relay: " + error);

  link::LinkEndpoints endpoints;
  endpoints.base_port = port;
  link::LinkClient client(endpoints, link::LinkClient::Options{.telemetry = true});
  ChildProcess xr({(bin / "telesphere-xr").string(), "offscreen", "--calib", calib, "--port", std::to_string(port),
                   "--video-link", "udp", "--media-port", std::to_string(relay->port()), "--head-link", "udp",
                   "--eye-size", "320x352",
                   "--rate", "60", "--duration", formatNumber(duration), "--out", (dir / "xr").string(), "--wait", "60"},
                  (dir / "xr.log").string());
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
  while (!(xr_code = xr.wait(std::chrono::milliseconds(20))) && Clock::now() < deadline) take();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  take();
  const int robot_code = robot.stop();
  const auto relay_stats = relay->stats();
  relay.reset();
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
  for (const auto& batch : robot_batches) frames_sent += static_cast<std::uint64_t>(batch.frames_size());
  if (shown.empty() || frames_sent == 0) throw std::runtime_error("network: no frame reached the display (" + dir.string() + ")");

  // The relay's clock started with the relay, before the XR app: map through the first packet.
  const double warmup_s = std::min(3.0, duration / 3);
  std::vector<double> g2g, ages, robot_ms, network_ms, operator_ms;
  std::set<std::uint64_t> sequences;
  double max_age = 0;
  for (const DisplayedFrame& f : shown) {
    sequences.insert(f.sequence);
    if (f.t_s < warmup_s) continue;
    ages.push_back(f.age_ms);
    max_age = std::max(max_age, f.age_ms);
    if (!f.new_image) continue;
    g2g.push_back(f.age_ms);
    robot_ms.push_back(f.robot_ms);
    network_ms.push_back(f.network_ms);
    operator_ms.push_back(f.operator_ms);
  }
  // Head targets at the robot: when sampled (robot clock, through the XR app's offset) to when the
  // head loop took them, for every tick that acted on a new one.
  std::vector<double> pose_age_ms;
  for (const auto& batch : robot_batches)
    for (const auto& tick : batch.ticks())
      if (tick.target_new() && tick.target_t_ns() > 0 && tick.target_arrival_ns() > tick.target_t_ns())
        pose_age_ms.push_back(static_cast<double>(tick.target_arrival_ns() - tick.target_t_ns()) * 1e-6);
  // Skip the start-up (the first third of a quick run, 3 s otherwise) by count: ticks are 100 Hz.
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
  double bytes_after_warmup = 0;
  std::int64_t first_ns = 0, last_ns = 0;
  {
    std::lock_guard lock(delivered_mutex);
    if (!delivered.empty()) first_ns = delivered.front().arrives_ns;
    for (const Delivered& d : delivered) {
      if (static_cast<double>(d.arrives_ns - first_ns) * 1e-9 < warmup_s) continue;
      queue_ms.push_back(static_cast<double>(d.left_bottleneck_ns - d.offered_ns) * 1e-6);
      bytes_after_warmup += static_cast<double>(d.bytes > link::media::kMediaHeaderBytes ? d.bytes - link::media::kMediaHeaderBytes : 0);
      last_ns = d.arrives_ns;
    }
  }
  // Capacity over the same window (the relay's clock: the rate trace counts from its start).
  double capacity_bits = 0;
  const std::int64_t from_ns = first_ns + static_cast<std::int64_t>(warmup_s * 1e9);
  for (std::int64_t t = from_ns; t < last_ns; t += 10'000'000) capacity_bits += trace->bitsPerSecondAt(t) * 0.01;
  const double goodput = capacity_bits > 0 ? 8.0 * bytes_after_warmup / capacity_bits : std::nan("");

  // Recovery after each rate step (relay clock → seconds after the step).
  nlohmann::json steps = nlohmann::json::array();
  if (!o.rate_steps.empty()) {
    // The trace's own steps (RateTrace::parseSteps read --rate-steps), the one at 0 s left out.
    std::vector<std::pair<double, double>> parsed;  // (t s, Mbit/s)
    for (const impairment::RateStep& step : trace->rateSteps())
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
        // Until 250 ms of delivered payload reach 80 % of the new capacity.
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

  const double frames_whole = xr_stats.value("media_frames_whole", 0.0);
  nlohmann::json media = {
      {"goodput_fraction", numberOrNull(goodput)},
      {"glass_to_glass_p50_ms", numberOrNull(quantileOr(g2g, 0.5))},
      {"glass_to_glass_p99_ms", numberOrNull(quantileOr(g2g, 0.99))},
      {"added_queuing_p95_ms", numberOrNull(quantileOr(queue_ms, 0.95))},
      {"frames_complete_fraction", frames_whole / static_cast<double>(frames_sent)},
      {"frames_shown_fraction", static_cast<double>(sequences.size()) / static_cast<double>(frames_sent)},
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
      {"frames_with_lost_bands", xr_stats.value("media_frames_concealed", 0)},
      {"frames_lost", xr_stats.value("media_frames_lost", 0)},
      {"bands_lost", xr_stats.value("media_bands_lost", 0)},
      {"rows_painted_from_previous", xr_stats.value("rows_concealed", 0)},
      {"relay_lost", relay_stats.to_client.lost},
      {"relay_dropped_at_queue", relay_stats.to_client.dropped_queue},
      {"rate_steps", steps}};
  // The keys: the first step down's and the first step up's recovery (null: no such step,
  // or not reached).
  media["recover_down_s"] = nullptr;
  media["recover_up_s"] = nullptr;
  for (const auto& step : steps) {
    if (step.contains("recover_down_s") && media["recover_down_s"].is_null()) media["recover_down_s"] = step["recover_down_s"];
    if (step.contains("recover_up_s") && media["recover_up_s"].is_null()) media["recover_up_s"] = step["recover_up_s"];
  }
  const std::string recover_down = [&] {
    for (const auto& s : steps) if (s.contains("recover_down_s")) return formatNumber(s["recover_down_s"].get<double>());
    return std::string("-");
  }();
  const std::string recover_up = [&] {
    for (const auto& s : steps)
      if (s.contains("recover_up_s")) return s["recover_up_s"].is_null() ? std::string("not reached") : formatNumber(s["recover_up_s"].get<double>());
    return std::string("-");
  }();

  Table table({"link", "goodput", "g2g p50 ms", "g2g p99 ms", "queue p95 ms", "complete", "shown", "max age ms",
               "pose p99 ms", "pose late", "recover down s", "recover up s"});
  table.addRow({"media path (UDP)", formatNumber(goodput), formatNumber(quantileOr(g2g, 0.5)),
                formatNumber(quantileOr(g2g, 0.99)), formatNumber(quantileOr(queue_ms, 0.95)),
                formatNumber(frames_whole / static_cast<double>(frames_sent)),
                formatNumber(static_cast<double>(sequences.size()) / static_cast<double>(frames_sent)),
                formatNumber(max_age), formatNumber(quantileOr(pose_age_ms, 0.99)), formatNumber(pose_late), recover_down,
                recover_up});
  table.addRow({"ZeroMQ/TCP (baseline)", "not measured", "-", "-", "-", "-", "-", "-", "-", "-", "-", "-"});
  table.print(ctx.out);
  ctx.out << "glass to glass p50: capture → sent " << formatNumber(quantileOr(robot_ms, 0.5)) << " ms (robot), sent → received "
          << formatNumber(quantileOr(network_ms, 0.5)) << " ms (path), received → displayed "
          << formatNumber(quantileOr(operator_ms, 0.5)) << " ms (operator); the video sent: "
          << formatNumber(source_mbit) << " Mbit/s of JPEG\n";
  ctx.out << "frames sent " << frames_sent << ", with lost bands " << xr_stats.value("media_frames_concealed", 0)
          << ", lost " << xr_stats.value("media_frames_lost", 0) << "; relay: " << relay_stats.to_client.lost
          << " lost, " << relay_stats.to_client.dropped_queue << " dropped at its queue\n"
          << "baseline not measured: today's link is TCP, and the relay acts on UDP datagrams; measuring it\n"
          << "through the same path needs a relay on IP packets (a TUN pair in a network namespace).\n"
          << "head targets on the media path only (--head-link udp); pose late = older than one-way + 100 ms\n"
          << "logs: " << dir.string() << "\n";

  return {{"rtt_ms", o.rtt_ms},
          {"jitter_ms", o.jitter_ms},
          {"loss", o.loss},
          {"loss_burst", o.loss_burst},
          {"rate_mbit", o.rate_mbit},
          {"rate_steps", o.rate_steps},
          {"duration_s", duration},
          {"size", o.size},
          {"fps", o.fps},
          {"media", media},
          {"baseline", {{"measured", false},
                        {"why", "today's ZeroMQ/TCP link through the same path needs a relay on IP packets (TUN)"}}}};
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
    },
    telesphere::bench::runNetwork});
