// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench pipeline`: the video path end to end on loopback (DESIGN.md §4) —
///        two replay cameras (pre-rendered synthetic frames, so rendering costs nothing) → stereo
///        pairing → parallel JPEG encode → link (real ZeroMQ over TCP loopback) → decode pool →
///        newest decoded pair — at 2×4K and 2×1080p. Per resolution it runs at 45 Hz and, if the
///        machine does not sustain that, at lower rates until it does, and reports the rate, the
///        latency capture → decoded (p50, p99), the per-stage split, bandwidth and drops. The floor
///        is the codec itself: one single-core encode plus one decode of the same frame, measured
///        in the same run; the goal is p50 ≤ 1.25 × floor.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "robot/video/jpeg_encoder.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/prerendered_frames.h"
#include "app/bench/replay_video_source.h"
#include "xr/video/jpeg_decoder.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::bench {
namespace {

using namespace std::chrono_literals;

struct PipelineResolution {
  const char* key;  ///< json suffix
  int width, height;
};

/// One single-core encode plus one decode of `frame` (median of `reps`), and the JPEG size.
double codecFloorMs(const robot::cameras::CameraFrame& frame, const robot::video::JpegSettings& settings, int reps,
                    std::size_t* jpeg_bytes) {
  robot::video::JpegEncoder encoder;
  xr::video::JpegDecoder decoder;
  std::vector<std::uint8_t> jpeg;
  xr::render::YuvPlanes planes;
  std::vector<double> ms;
  std::string error;
  for (int i = 0; i < reps + 1; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    encoder.encodeRgb(frame.pixels->data(), frame.width, frame.height, frame.stride_bytes, settings,
                      jpeg, &error);
    decoder.decode(jpeg, frame.width, frame.height, 8192, planes, &error);
    const auto t1 = std::chrono::steady_clock::now();
    if (i > 0) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  *jpeg_bytes = jpeg.size();
  return quantile(ms, 0.5);
}

struct PipelineRun {
  double rate_hz = 0;
  std::uint64_t sent = 0, decoded_seen = 0, camera_lost = 0, dropped = 0;
  double p50_ms = 0, p99_ms = 0, bandwidth_mb_s = 0;
  xr::video::StereoDecodeStats decode;
  bool sustained = false;
};

PipelineRun runPipeline(const std::vector<robot::cameras::CameraFrame>& left_frames,
                        const std::vector<robot::cameras::CameraFrame>& right_frames, double rate_hz,
                        double seconds, int port) {
  link::LinkEndpoints endpoints;
  endpoints.base_port = port;
  ReplayVideoSource robot_side(endpoints, left_frames, right_frames, rate_hz, {}, 300ms);
  link::LinkClient client(endpoints);
  xr::video::StereoFrameDecoder decoder(client);

  // Warm-up: the first second is not counted (connections, caches, buffer pools).
  const auto warm_end = std::chrono::steady_clock::now() + 300ms + 1s;
  const auto end = warm_end + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(seconds));
  std::vector<double> latency_ms;
  std::uint64_t last_sequence = 0, sent_at_warm = 0, lost_at_warm = 0, bytes = 0;
  bool warm = false;
  while (std::chrono::steady_clock::now() < end) {
    auto frame = decoder.waitNewer(last_sequence, 200ms);
    if (!warm && std::chrono::steady_clock::now() >= warm_end) {
      warm = true;
      sent_at_warm = robot_side.streamer.stats().frames_sent;
      lost_at_warm = robot_side.left.stats().lost + robot_side.right.stats().lost;
    }
    if (!frame) continue;
    last_sequence = frame->frame.sequence();
    if (!warm) continue;
    const auto& stamps = frame->frame.stamps();
    latency_ms.push_back(double(stamps.decoded_ns() - stamps.capture_ns()) * 1e-6);
    bytes += frame->frame.left().jpeg_bytes() + frame->frame.right().jpeg_bytes();
  }
  PipelineRun run;
  run.rate_hz = rate_hz;
  run.sent = robot_side.streamer.stats().frames_sent - sent_at_warm;
  run.camera_lost = robot_side.left.stats().lost + robot_side.right.stats().lost - lost_at_warm;
  run.decoded_seen = latency_ms.size();
  run.dropped = run.sent > run.decoded_seen ? run.sent - run.decoded_seen : 0;
  const xr::video::LatencyFigure latency = xr::video::latencyFigure(latency_ms);
  run.p50_ms = latency.p50_ms;
  run.p99_ms = latency.p99_ms;
  const double mean_bytes = latency_ms.empty() ? 0.0 : double(bytes) / double(latency_ms.size());
  run.bandwidth_mb_s = mean_bytes * double(run.sent) / seconds * 1e-6;
  run.decode = decoder.stats();
  const double expected = rate_hz * seconds;
  run.sustained = double(run.decoded_seen) >= 0.95 * expected && run.camera_lost <= expected * 0.05;
  return run;
}

std::string ms(const xr::video::LatencyFigure& f) {
  return formatNumber(f.p50_ms) + " / " + formatNumber(f.p99_ms);
}

nlohmann::json runPipelineBench(const BenchContext& ctx) {
  nlohmann::json json;
  const std::vector<PipelineResolution> resolutions = {{"4k", 3840, 2160}, {"1080p", 1920, 1080}};
  const std::vector<double> rates = {45.0, 30.0, 22.5, 15.0, 10.0, 5.0};
  const double seconds = ctx.quick ? 2.0 : 10.0;
  const robot::video::JpegSettings settings;  // quality 90, 4:2:0: the robot's default
  Table summary({"stereo input", "rate Hz", "sustained", "p50 ms", "p99 ms", "floor ms",
                 "p50/floor", "MB/s", "sent", "dropped", "camera lost"});
  Table stages({"stereo input", "capture→encoded", "encoded→sent", "sent→received",
                "received→decoded", "decode (1 JPEG)", "capture→decoded"});
  int port = 27400;
  for (const auto& res : resolutions) {
    ctx.out << "pipeline: rendering " << res.width << "x" << res.height << " frames…\n" << std::flush;
    const int count = ctx.quick ? 2 : 4;
    const auto left = prerender(res.width, res.height, 0.032, count);
    const auto right = prerender(res.width, res.height, -0.032, count);
    std::size_t jpeg_bytes = 0;
    const double floor_ms = codecFloorMs(left[0], settings, ctx.quick ? 3 : 9, &jpeg_bytes);
    PipelineRun best;
    for (double rate : rates) {
      ctx.out << "pipeline: " << res.key << " at " << rate << " Hz…\n" << std::flush;
      best = runPipeline(left, right, rate, seconds, port);
      port += 10;
      if (best.sustained) break;
    }
    const std::string name = std::string("2×") + res.key;
    summary.addRow({name, formatNumber(best.rate_hz), best.sustained ? "yes" : "no",
                    formatNumber(best.p50_ms), formatNumber(best.p99_ms), formatNumber(floor_ms),
                    formatNumber(best.p50_ms / floor_ms), formatNumber(best.bandwidth_mb_s),
                    std::to_string(best.sent), std::to_string(best.dropped),
                    std::to_string(best.camera_lost)});
    stages.addRow({name, ms(best.decode.capture_to_encoded), ms(best.decode.encoded_to_sent),
                   ms(best.decode.sent_to_received), ms(best.decode.received_to_decoded),
                   ms(best.decode.decode), ms(best.decode.capture_to_decoded)});
    const std::string k = res.key;
    json["latency_p50_ms_" + k] = best.p50_ms;
    json["latency_p99_ms_" + k] = best.p99_ms;
    json["codec_floor_ms_" + k] = floor_ms;
    json["rate_hz_" + k] = best.rate_hz;
    json["sustained_" + k] = best.sustained;
    json["bandwidth_mb_s_" + k] = best.bandwidth_mb_s;
    json["dropped_" + k] = best.dropped;
    json["jpeg_bytes_" + k] = jpeg_bytes;
  }
  ctx.out << "\nEnd to end on loopback, JPEG quality 90 4:2:0, " << seconds
          << " s per rate after 1 s warm-up; latency = capture → both images decoded; floor = one "
             "single-core encode + decode of one image\n";
  summary.print(ctx.out);
  ctx.out << "\nPer stage, p50 / p99 ms\n";
  stages.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(pipeline, telesphere::bench::BenchTopic{
                                     "pipeline",
                                     "video path end to end on loopback: cameras → encode → link "
                                     "→ decode, latency vs the codec floor",
                                     {},
                                     telesphere::bench::runPipelineBench});
