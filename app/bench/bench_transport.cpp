// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench transport`: the media path's two designs side by side (issue #32),
///        the same stereo JPEG frames through the same impaired UDP relay on loopback:
///        - ours: MediaSender / MediaReceiver (frames sliced along restart intervals, Reed–Solomon
///          parity, retransmission only while the frame is due, paced by the delay-based rate
///          controller, the oldest unsent frame dropped);
///        - SRT: the same datagrams (without parity) as libsrt live-mode messages, retransmitted
///          until the play-out deadline (latency ≈ one RTT, SRTO_TLPKTDROP), reassembled by the
///          same FrameAssembler, so lost bands count alike.
///        The source does not adapt (a fixed rate of real JPEGs of the synthetic scene), so what
///        differs is only the transport. Prints a table per scenario; figures after a warm-up.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <cstdio>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/impairment/udp_relay.h"
#include "app/bench/prerendered_frames.h"
#include "app/bench/srt/srt_frame_link.h"
#include "robot/link/media/frame_assembler.h"
#include "robot/link/media/frame_packetizer.h"
#include "robot/link/media/media_receiver.h"
#include "robot/link/media/media_sender.h"
#include "robot/video/jpeg_encoder.h"

namespace telesphere::bench {
namespace {

using namespace std::chrono_literals;
namespace media = link::media;
using impairment::PathOptions;
using impairment::RateTrace;

struct TransportOptions {
  double duration_s = 10.0;
  double warmup_s = 2.0;
  std::string size = "960x540";
  double fps = 30.0;
  double source_mbit = 12.0;
  std::vector<double> srt_latency_rtts = {1.0, 3.0};  ///< one SRT run per entry
};

TransportOptions& transportOptions() {
  static TransportOptions o;
  return o;
}

struct Scenario {
  std::string name;
  double rtt_ms = 100, jitter_ms = 0, loss = 0, loss_burst = 1, rate_mbit = 20;
  std::string rate_steps;  ///< "T:M,…" seconds from the start of the measured part
};

/// The frames sent, encoded once: a moving camera's stereo pairs at the chosen quality.
struct Source {
  std::vector<std::pair<std::vector<std::uint8_t>, std::vector<std::uint8_t>>> frames;
  int width = 0, height = 0, quality = 0;
  double mbit_per_s = 0;
};

Source encodeSource(const TransportOptions& o) {
  Source s;
  if (std::sscanf(o.size.c_str(), "%dx%d", &s.width, &s.height) != 2 || s.width < 64 || s.height < 64)
    throw std::runtime_error("transport: --size must be WxH (at least 64x64)");
  const auto left = prerender(s.width, s.height, 0.032, 8);
  const auto right = prerender(s.width, s.height, -0.032, 8);
  robot::video::JpegEncoder encoder;
  std::string error;
  // The highest quality whose stereo stream fits the source rate (restart marker every MCU row,
  // as the robot sends on the media path).
  for (int q = 95; q >= 5; q -= 5) {
    s.frames.clear();
    double bytes = 0;
    for (std::size_t i = 0; i < left.size(); ++i) {
      std::vector<std::uint8_t> l, r;
      const robot::video::JpegSettings settings{q, link::ChromaSubsampling::k420, 1};
      for (auto [frame, jpeg] : {std::pair{&left[i], &l}, std::pair{&right[i], &r}})
        if (!encoder.encodeRgb(frame->pixels->data(), frame->width, frame->height, frame->stride_bytes, settings, *jpeg,
                               &error))
          throw std::runtime_error("transport: encode: " + error);
      bytes += double(l.size() + r.size());
      s.frames.emplace_back(std::move(l), std::move(r));
    }
    s.quality = q;
    s.mbit_per_s = bytes / double(left.size()) * 8.0 * o.fps / 1e6;
    if (s.mbit_per_s <= o.source_mbit) break;
  }
  return s;
}

PathOptions pathOptions(const Scenario& sc, bool downlink, double warmup_s) {
  PathOptions path;
  path.one_way_delay_ns = std::int64_t(sc.rtt_ms * 0.5e6);
  path.jitter_ns = std::int64_t(sc.jitter_ms * 0.25e6);
  path.loss.loss_fraction = sc.loss;
  path.loss.mean_burst_packets = sc.loss_burst;
  path.loss.seed = downlink ? 5 : 6;
  if (downlink) {
    std::string error;
    // Steps are given from the start of the measured part; the relay's clock starts with the
    // warm-up (the connection takes milliseconds before it).
    std::string steps;
    if (!sc.rate_steps.empty()) {
      std::stringstream in(sc.rate_steps);
      std::string step;
      while (std::getline(in, step, ',')) {
        const auto colon = step.find(':');
        steps += (steps.empty() ? "" : ",") + formatNumber(std::stod(step.substr(0, colon)) + warmup_s, 6) +
                 step.substr(colon);
      }
    }
    auto trace = steps.empty() ? RateTrace::constant(sc.rate_mbit * 1e6) : RateTrace::parseSteps(sc.rate_mbit * 1e6, steps, &error);
    if (!trace) throw std::runtime_error("transport: " + error);
    path.rate = *trace;
  }
  return path;
}

/// What a receiver handed over: the frame's sequence, when, whole or not.
struct Delivery {
  std::uint64_t sequence = 0;
  std::int64_t at_ns = 0;
  bool whole = false;
  std::size_t jpeg_bytes = 0;
};

struct Figures {
  std::string transport;
  double shown = 0, whole = 0, latency_p50_ms = 0, latency_p99_ms = 0, latency_max_ms = 0, goodput_mbit = 0;
  double wire_overhead = 0;
  double shown_bytes_all = 0;  ///< JPEG bytes of every frame out, warm-up included
  std::uint64_t repaired = 0, late = 0;  ///< chunks retransmitted; packets dropped too late (SRT) / chunks asked for in vain
  std::string detail;
};

std::int64_t steadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Offers the source's frames at o.fps for warm-up + duration through `send`; returns each
/// sequence's offer time.
std::map<std::uint64_t, std::int64_t> offerFrames(const TransportOptions& o, double duration_s, const Source& source,
                                                  const std::function<void(const link::proto::StereoFrame&,
                                                                           const std::vector<std::uint8_t>&,
                                                                           const std::vector<std::uint8_t>&)>& send) {
  std::map<std::uint64_t, std::int64_t> offered;
  const std::size_t count = std::size_t((o.warmup_s + duration_s) * o.fps);
  auto next = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < count; ++i) {
    const auto& [left, right] = source.frames[i % source.frames.size()];
    link::proto::StereoFrame frame;
    frame.set_sequence(i);
    for (auto* image : {frame.mutable_left(), frame.mutable_right()}) {
      image->set_width(std::uint32_t(source.width));
      image->set_height(std::uint32_t(source.height));
    }
    offered[i] = steadyNowNs();
    send(frame, left, right);
    next += std::chrono::nanoseconds(std::int64_t(1e9 / o.fps));
    std::this_thread::sleep_until(next);
  }
  return offered;
}

/// The figures over the frames offered after the warm-up.
Figures summarise(const TransportOptions& o, double duration_s, const std::map<std::uint64_t, std::int64_t>& offered,
                  const std::vector<Delivery>& delivered) {
  Figures f;
  const std::uint64_t first = std::uint64_t(o.warmup_s * o.fps);
  std::vector<double> latency_ms;
  std::size_t shown = 0, whole = 0;
  double bytes = 0;
  for (const Delivery& d : delivered) {
    f.shown_bytes_all += double(d.jpeg_bytes);
    if (d.sequence < first) continue;
    const auto it = offered.find(d.sequence);
    if (it == offered.end()) continue;
    ++shown;
    whole += d.whole ? 1 : 0;
    bytes += double(d.jpeg_bytes);
    latency_ms.push_back(double(d.at_ns - it->second) * 1e-6);
  }
  const double measured = double(offered.size()) - double(first);
  f.shown = measured > 0 ? double(shown) / measured : 0;
  f.whole = shown > 0 ? double(whole) / double(shown) : 0;
  f.latency_p50_ms = quantile(latency_ms, 0.5);
  f.latency_p99_ms = quantile(latency_ms, 0.99);
  f.latency_max_ms = latency_ms.empty() ? 0 : *std::max_element(latency_ms.begin(), latency_ms.end());
  f.goodput_mbit = bytes * 8.0 / duration_s / 1e6;
  return f;
}

std::unique_ptr<impairment::UdpRelay> startRelay(const Scenario& sc, const TransportOptions& o, std::uint16_t server_port) {
  impairment::UdpRelayOptions relay_options;
  relay_options.server_port = server_port;
  relay_options.to_server = pathOptions(sc, false, o.warmup_s);
  relay_options.to_client = pathOptions(sc, true, o.warmup_s);
  std::string error;
  auto relay = impairment::UdpRelay::start(relay_options, &error);
  if (!relay) throw std::runtime_error("transport: relay: " + error);
  return relay;
}

/// What the path carried towards the receiver per JPEG byte shown, less 1 (the whole run).
double wirePerShownByte(const impairment::UdpRelayStats& relay, const Figures& f) {
  return f.shown_bytes_all > 0 ? double(relay.to_client.bytes_offered) / f.shown_bytes_all - 1.0 : 0.0;
}

Figures runOurs(const Scenario& sc, const TransportOptions& o, double duration_s, const Source& source) {
  std::string error;
  media::MediaSenderOptions so;
  so.bind_address = "127.0.0.1";
  auto sender = media::MediaSender::start(so, &error);
  if (!sender) throw std::runtime_error("transport: media sender: " + error);
  auto relay = startRelay(sc, o, sender->port());
  media::MediaReceiverOptions ro;
  ro.sender_port = relay->port();
  ro.assembler.repair = true;
  auto receiver = media::MediaReceiver::start(ro, &error);
  if (!receiver) throw std::runtime_error("transport: media receiver: " + error);
  receiver->setRoundTripHintNs(std::int64_t(sc.rtt_ms * 1e6));  // the XR app has it from the clock sync
  for (int i = 0; i < 300 && !sender->hasReceiver(); ++i) std::this_thread::sleep_for(10ms);
  if (!sender->hasReceiver()) throw std::runtime_error("transport: no hello reached the media sender");

  std::vector<Delivery> delivered;
  std::atomic<bool> done{false};
  std::thread consumer([&] {
    const auto take = [&](std::chrono::milliseconds wait) {
      auto f = receiver->waitNewest(wait);
      if (f) delivered.push_back({f->stereo.sequence(), steadyNowNs(), f->whole(), f->left_jpeg.size() + f->right_jpeg.size()});
      return f.has_value();
    };
    while (!done) take(5ms);
    while (take(500ms)) {
    }
  });
  std::string send_error;  // thrown once the consumer has stopped
  const auto offered = offerFrames(o, duration_s, source, [&](const auto& frame, const auto& left, const auto& right) {
    std::string e;
    if (!sender->sendFrame(frame, left, right, &e) && send_error.empty()) send_error = "transport: send: " + e;
  });
  done = true;
  consumer.join();
  if (!send_error.empty()) throw std::runtime_error(send_error);
  Figures f = summarise(o, duration_s, offered, delivered);
  f.transport = "ours (RS + ARQ while due)";
  const auto ss = sender->stats();
  const auto rs = receiver->stats();
  const auto relay_stats = relay->stats();
  f.wire_overhead = wirePerShownByte(relay_stats, f);
  f.repaired = ss.chunks_resent;
  f.late = rs.assembler.chunks_requested - rs.assembler.chunks_repaired;
  std::ostringstream detail;
  detail << "ours: " << ss.frames_superseded << " frames superseded at the sender, pacing " << formatNumber(ss.pacing_bps / 1e6)
         << " Mbit/s at the end; parity rebuilt " << rs.assembler.chunks_recovered << " chunks, " << ss.chunks_resent
         << " resent (" << rs.assembler.chunks_repaired << " of " << rs.assembler.chunks_requested
         << " asked for arrived); relay lost " << relay_stats.to_client.lost << ", dropped at its queue "
         << relay_stats.to_client.dropped_queue << "\n";
  f.detail = detail.str();
  return f;
}

Figures runSrt(const Scenario& sc, const TransportOptions& o, double duration_s, const Source& source, double latency_rtts) {
  std::string error;
  srt::SrtLinkOptions lo;
  lo.latency_ms = std::max(20, int(sc.rtt_ms * latency_rtts + 0.5));
  auto sender = srt::SrtSender::listen(lo, 0, &error);
  if (!sender) throw std::runtime_error("transport: " + error);
  auto relay = startRelay(sc, o, sender->port());

  // The same framing without parity (SRT repairs by retransmission); the header chunks still sent twice.
  media::FramePacketizer::Config packetizer_config;
  packetizer_config.fec_overhead = 0;
  media::FramePacketizer packetizer(0x5e7, packetizer_config);
  media::FrameAssembler assembler;  // no repair requests: SRT's own
  std::mutex mutex;
  std::vector<Delivery> delivered;
  std::vector<media::AssembledFrame> out;
  const auto take = [&] {
    for (const auto& f : out)
      delivered.push_back({f.stereo.sequence(), steadyNowNs(), f.whole(), f.left_jpeg.size() + f.right_jpeg.size()});
    out.clear();
  };
  auto receiver = srt::SrtReceiver::connect(
      lo, relay->port(),
      [&](std::span<const std::uint8_t> datagram, std::int64_t now_ns) {
        std::lock_guard lock(mutex);
        assembler.add(datagram, now_ns, out);
        take();
      },
      [&](std::int64_t now_ns) {
        std::lock_guard lock(mutex);
        assembler.expire(now_ns, out);
        take();
      },
      &error);
  if (!receiver) throw std::runtime_error("transport: " + error);
  if (!sender->accept(3000, &error)) throw std::runtime_error("transport: " + error);

  std::uint32_t seq = 0;
  std::uint64_t send_failures = 0;
  const auto offered = offerFrames(o, duration_s, source, [&](const auto& frame, const auto& left, const auto& right) {
    media::PacketizedFrame packets;
    std::string e;
    if (!packetizer.packetize(frame, left, right, &packets, &e)) throw std::runtime_error("transport: packetize: " + e);
    const auto send_us = std::uint32_t(steadyNowNs() / 1000);
    for (auto& datagram : packets.datagrams) {
      media::stampForSending(datagram, seq++, send_us);
      if (!sender->send(datagram, &e)) ++send_failures;
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(lo.latency_ms + int(sc.rtt_ms) + 300));
  const auto ss = sender->stats();
  const auto rs = receiver->stats();
  receiver.reset();
  Figures f;
  {
    std::lock_guard lock(mutex);
    f = summarise(o, duration_s, offered, delivered);
  }
  f.transport = "SRT live, latency " + std::to_string(lo.latency_ms) + " ms (" + formatNumber(latency_rtts) + " RTT)";
  const auto relay_stats = relay->stats();
  f.wire_overhead = wirePerShownByte(relay_stats, f);
  f.repaired = std::uint64_t(ss.packets_retransmitted);
  f.late = std::uint64_t(rs.packets_dropped_late + ss.packets_dropped_late);
  std::ostringstream detail;
  detail << "SRT: " << ss.packets_sent << " packets, " << ss.packets_retransmitted << " retransmitted, "
         << rs.packets_dropped_late << " dropped too late at the receiver, " << ss.packets_dropped_late
         << " at the sender, " << send_failures << " sends refused; RTT " << formatNumber(ss.rtt_ms)
         << " ms; relay lost " << relay_stats.to_client.lost << ", dropped at its queue "
         << relay_stats.to_client.dropped_queue << "\n";
  f.detail = detail.str();
  return f;
}

nlohmann::json figuresJson(const Figures& f) {
  return {{"transport", f.transport},         {"frames_shown_fraction", f.shown},
          {"frames_whole_fraction", f.whole}, {"latency_p50_ms", f.latency_p50_ms},
          {"latency_p99_ms", f.latency_p99_ms}, {"latency_max_ms", f.latency_max_ms},
          {"goodput_mbit", f.goodput_mbit},   {"wire_overhead", f.wire_overhead},
          {"repaired", f.repaired},           {"late", f.late}};
}

nlohmann::json runTransport(const BenchContext& ctx) {
  const TransportOptions& o = transportOptions();
  const double duration = ctx.quick ? std::min(o.duration_s, 4.0) : o.duration_s;
  TransportOptions run_options = o;
  if (ctx.quick) run_options.warmup_s = std::min(o.warmup_s, 1.0);
  const Source source = encodeSource(o);
  ctx.out << "transport: " << source.width << "x" << source.height << " stereo JPEG q" << source.quality << " at "
          << formatNumber(o.fps) << " Hz = " << formatNumber(source.mbit_per_s) << " Mbit/s (fixed, not adapted), "
          << formatNumber(duration) << " s measured after " << formatNumber(run_options.warmup_s)
          << " s warm-up, each scenario both ways through the UDP relay on loopback…\n"
          << std::flush;
  std::vector<Scenario> scenarios = {
      {"LAN-like: 20 ms, no loss, 20 Mbit/s", 20, 0, 0, 1, 20, ""},
      {"100 ms ± 10, 1 % loss, 20 Mbit/s", 100, 10, 0.01, 1, 20, ""},
      {"100 ms, 1 % loss in bursts of 5, 20 Mbit/s", 100, 0, 0.01, 5, 20, ""},
      {"200 ms ± 10, 2 % loss, 20 Mbit/s", 200, 10, 0.02, 1, 20, ""},
      {"100 ms, 1 % loss, 20 → 5 Mbit/s at half time", 100, 0, 0.01, 1, 20, formatNumber(duration / 2) + ":5"},
  };
  if (ctx.quick) scenarios = {scenarios[1], scenarios[4]};
  Table table({"scenario", "transport", "shown", "whole", "latency p50 ms", "p99 ms", "max ms", "goodput Mbit/s",
               "wire / shown", "resent", "too late"});
  nlohmann::json runs = nlohmann::json::array();
  std::string details;
  for (const Scenario& sc : scenarios) {
    for (std::size_t t = 0; t <= o.srt_latency_rtts.size(); ++t) {
      const Figures f = t == 0 ? runOurs(sc, run_options, duration, source)
                               : runSrt(sc, run_options, duration, source, o.srt_latency_rtts[t - 1]);
      table.addRow({sc.name, f.transport, formatNumber(f.shown), formatNumber(f.whole), formatNumber(f.latency_p50_ms),
                    formatNumber(f.latency_p99_ms), formatNumber(f.latency_max_ms), formatNumber(f.goodput_mbit),
                    formatNumber(100 * f.wire_overhead) + " %", std::to_string(f.repaired), std::to_string(f.late)});
      details += sc.name + " — " + f.detail;
      nlohmann::json j = figuresJson(f);
      j["scenario"] = sc.name;
      runs.push_back(j);
      ctx.out << "  " << sc.name << ", " << f.transport << ": shown " << formatNumber(f.shown) << ", p99 "
              << formatNumber(f.latency_p99_ms) << " ms\n" << std::flush;
    }
  }
  table.print(ctx.out);
  ctx.out << details
          << "latency = offered to the transport → whole or concealed frame out of the receiver (same clock);\n"
          << "shown = frames out / frames offered; whole = of those, without a filled band; wire / shown = bytes\n"
          << "the relay was offered towards the receiver / JPEG bytes shown, less 1; resent = chunks (ours) or\n"
          << "packets (SRT) sent again; too late = chunks asked for in vain (ours) or packets SRT dropped as late\n";
  return {{"size", o.size},           {"fps", o.fps},           {"quality", source.quality},
          {"source_mbit", source.mbit_per_s}, {"duration_s", duration}, {"srt_latency_rtts", o.srt_latency_rtts},
          {"runs", runs}};
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(transport, telesphere::bench::BenchTopic{
    "transport",
    "the media path's two designs on the same frames and path: our framing (RS parity + retransmission while due) "
    "against SRT live mode",
    [](CLI::App& sub) {
      auto& o = telesphere::bench::transportOptions();
      sub.add_option("--duration", o.duration_s, "seconds measured per run")->capture_default_str()->check(CLI::Range(2.0, 600.0));
      sub.add_option("--size", o.size, "each eye's image, WxH")->capture_default_str();
      sub.add_option("--fps", o.fps, "frames per second")->capture_default_str()->check(CLI::Range(1.0, 120.0));
      sub.add_option("--source-mbit", o.source_mbit, "the stream's rate: the highest JPEG quality that fits")
          ->capture_default_str()->check(CLI::Range(0.5, 1000.0));
      sub.add_option("--srt-latency-rtts", o.srt_latency_rtts, "SRT's latency windows in round trips (one run each)")
          ->capture_default_str()->delimiter(',')->check(CLI::Range(0.25, 10.0));
    },
    telesphere::bench::runTransport});
