// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench pipeline`: the video path end to end on loopback (DESIGN.md §4) —
///        two replay cameras (pre-rendered synthetic frames, so rendering costs nothing) → stereo
///        pairing → parallel JPEG encode → link (real ZeroMQ over TCP loopback) → decode pool →
///        newest decoded pair — at 2×4K and 2×1080p. Per resolution it runs at 45 Hz and, if the
///        machine does not sustain that, at lower rates until it does, and reports the rate, the
///        latency capture → decoded (p50, p99), the per-stage split, bandwidth and drops. The floor
///        is the codec itself: one single-core encode plus one decode of the same frame, measured
///        in the same run; the goal is p50 ≤ 1.25 × floor. Then the cost of encryption (DESIGN.md
///        §10): the same rate with CURVE keys on every socket against none, latency p50 and CPU
///        time per stereo frame (robot and client ends together, both in this process); goal
///        ≤ 2 % more CPU and ≤ 0.5 ms more latency per frame. And 2×4K as the cameras send it,
///        a raw Bayer mosaic (#34): debayered into planes by the encoder, against the same floor
///        from the mosaic (debayer + encode + decode of one image). And 2×1080p as H.264 and HEVC
///        at 20 Mbit/s (#34, libavcodec on the CPU), against the floor of that codec: one
///        single-threaded encode + decode of a predicted image in the same sequence.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <vector>

#include "robot/cameras/debayer_yuv420.h"
#include "robot/video/av_video_encoder.h"
#include "robot/video/frame_to_yuv420.h"
#include "robot/video/jpeg_encoder.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/prerendered_frames.h"
#include "app/bench/replay_video_source.h"
#include "robot/link/media/media_packet.h"
#include "robot/link/media/media_seal.h"
#include "robot/link/trust/link_key_files.h"
#include "xr/video/av_video_decoder.h"
#include "xr/video/jpeg_decoder.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::bench {
namespace {

using namespace std::chrono_literals;

struct PipelineResolution {
  const char* key;  ///< json suffix
  int width, height;
  bool bayer = false;  ///< the cameras send an RGGB mosaic (no CURVE rounds for it)
  link::VideoCodec codec = link::VideoCodec::kMjpeg;  ///< H.264/HEVC: no CURVE rounds either
};

/// The H.264/HEVC link rate of the codec rows (both cameras together), Mbit/s.
constexpr double kPipelineVideoMbit = 20.0;

/// H.264/HEVC: one single-threaded encode plus one decode of a predicted image (median over a
/// sequence of `frames` cycled `reps` times; the first, a key frame, not counted), and the mean
/// access unit's size.
double videoFloorMs(const std::vector<robot::cameras::CameraFrame>& frames, link::VideoCodec codec, int reps,
                    std::size_t* bytes_per_image) {
  robot::video::FrameToYuv420 to_planes;
  robot::cameras::Yuv420Image planes;
  robot::video::AvVideoEncoderOptions o;
  o.codec = codec;
  o.width = frames[0].width;
  o.height = frames[0].height;
  o.bit_rate_bps = static_cast<std::int64_t>(kPipelineVideoMbit * 1e6 / 2);
  o.threads = 1;
  std::string error;
  auto encoder = robot::video::AvVideoEncoder::open(o, &error);
  auto decoder = xr::video::AvVideoDecoder::open(codec, 1, &error);
  if (!encoder || !decoder) throw std::runtime_error("pipeline: " + error);
  robot::video::EncodedVideoFrame packet;
  xr::render::YuvPlanes decoded;
  std::vector<double> ms;
  std::size_t bytes = 0;
  const int images = reps * static_cast<int>(frames.size()) + 1;
  for (int i = 0; i < images; ++i) {
    const auto& frame = frames[static_cast<std::size_t>(i) % frames.size()];
    const auto t0 = std::chrono::steady_clock::now();
    if (!to_planes.convert(frame, planes, &error) || !encoder->encode(planes, i == 0, packet, &error) ||
        decoder->decode(packet.bytes, packet.key_frame, decoded, &error) != xr::video::AvDecodeResult::kFrame)
      throw std::runtime_error("pipeline: " + std::string(link::videoCodecName(codec)) + " floor: " + error);
    const auto t1 = std::chrono::steady_clock::now();
    if (i == 0) continue;
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    bytes += packet.bytes.size();
  }
  *bytes_per_image = bytes / ms.size();
  return quantile(ms, 0.5);
}

/// One single-core encode plus one decode of `frame` (median of `reps`), and the JPEG size; for a
/// Bayer mosaic the encode includes its debayering into planes.
double codecFloorMs(const robot::cameras::CameraFrame& frame, const robot::video::JpegSettings& settings, int reps,
                    std::size_t* jpeg_bytes) {
  robot::video::JpegEncoder encoder;
  xr::video::JpegDecoder decoder;
  std::vector<std::uint8_t> jpeg;
  xr::render::YuvPlanes planes;
  std::vector<double> ms;
  std::string error;
  robot::cameras::DebayerToYuv420 to_planes;
  robot::cameras::Yuv420Image mosaic_planes;
  for (int i = 0; i < reps + 1; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    if (robot::cameras::isBayer(frame.format)) {
      to_planes.convert(frame.pixels->data(), frame.width, frame.height, frame.stride_bytes, frame.format,
                        mosaic_planes, &error);
      encoder.encodeYuv420(mosaic_planes, settings, jpeg, &error);
    } else {
      encoder.encodeRgb(frame.pixels->data(), frame.width, frame.height, frame.stride_bytes, settings, jpeg, &error);
    }
    decoder.decode(jpeg, frame.width, frame.height, 8192, planes, &error);
    const auto t1 = std::chrono::steady_clock::now();
    if (i > 0) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  *jpeg_bytes = jpeg.size();
  return quantile(ms, 0.5);
}

/// CPU time of this whole process (every thread), ms.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

/// A robot key and a client key in a scratch folder, the robot trusting the client: what a keyed
/// link needs, made fresh for the run by libzmq.
struct PipelineKeys {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("telesphere-bench-pipeline-keys-" + std::to_string(::getpid()));
  link::trust::LinkCredentials robot, client;
  bool ok = false;

  PipelineKeys() {
    namespace trust = link::trust;
    std::filesystem::remove_all(dir);
    std::string error;
    const auto robot_pair = trust::generateKeyPair("bench-robot", trust::LinkRole::kRobot, &error);
    const auto client_pair = trust::generateKeyPair("bench-operator", trust::LinkRole::kOperator, &error);
    if (!robot_pair || !client_pair || !trust::writeKeyPair(*robot_pair, dir / "robot", false, &error) ||
        !trust::writeKeyPair(*client_pair, dir / "robot" / "allowed", false, &error))
      return;
    robot.own = *robot_pair;
    robot.allowed_dir = dir / "robot" / "allowed";
    client.own = *client_pair;
    client.robot_public_z85 = robot_pair->key.public_z85;
    ok = true;
  }
  ~PipelineKeys() { std::filesystem::remove_all(dir); }
};

/// Sealing and opening one stereo frame on the media path (two JPEGs of `jpeg_bytes` in chunks of
/// the largest datagram), ms on one core: the median of `reps`.
double mediaSealMs(std::size_t jpeg_bytes, int reps) {
  using namespace link::media;
  const MediaSealKey key = newMediaSealKey();
  MediaSealer sealer(key, SealDirection::kToReceiver);
  MediaOpener opener(key, SealDirection::kToReceiver);
  const std::vector<std::uint8_t> datagram(kMaxMediaDatagramBytes, 0x5A);
  const std::size_t datagrams = 2 * ((jpeg_bytes + kMaxChunkBytes - 1) / kMaxChunkBytes);
  std::vector<std::uint8_t> sealed, opened;
  std::vector<double> ms;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < datagrams; ++i) {
      SealRefusal why{};
      sealer.seal(datagram, sealed);
      if (!opener.open(sealed, opened, &why)) throw std::runtime_error("pipeline: a sealed datagram did not open");
    }
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return quantile(ms, 0.5);
}

struct PipelineRun {
  double cpu_ms_per_frame = 0;  ///< process CPU time (both ends) per decoded stereo frame
  double rate_hz = 0;
  std::uint64_t sent = 0, decoded_seen = 0, camera_lost = 0, dropped = 0;
  double p50_ms = 0, p99_ms = 0, bandwidth_mb_s = 0;
  xr::video::StereoDecodeStats decode;
  bool sustained = false;
};

PipelineRun runPipeline(const std::vector<robot::cameras::CameraFrame>& left_frames,
                        const std::vector<robot::cameras::CameraFrame>& right_frames, double rate_hz,
                        double seconds, int port, const PipelineKeys* keys = nullptr,
                        link::VideoCodec codec = link::VideoCodec::kMjpeg) {
  link::LinkEndpoints endpoints;
  endpoints.base_port = port;
  link::LinkEndpoints client_endpoints = endpoints;
  if (keys) {
    endpoints.credentials = keys->robot;
    client_endpoints.credentials = keys->client;
  }
  robot::video::VideoStreamerConfig config;
  config.codec = codec;
  config.video.bit_rate_bps = static_cast<std::int64_t>(kPipelineVideoMbit * 1e6);
  config.video.fps = static_cast<int>(std::lround(rate_hz));
  config.video.threads_per_camera = 1;
  ReplayVideoSource robot_side(endpoints, left_frames, right_frames, rate_hz, {}, 300ms, config);
  link::LinkClient client(client_endpoints);
  xr::video::StereoFrameDecoder decoder(client);

  // Warm-up: the first second is not counted (connections, caches, buffer pools).
  const auto warm_end = std::chrono::steady_clock::now() + 300ms + 1s;
  const auto end = warm_end + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(seconds));
  std::vector<double> latency_ms;
  std::uint64_t last_sequence = 0, sent_at_warm = 0, lost_at_warm = 0, bytes = 0;
  bool warm = false;
  double cpu_at_warm = 0;
  while (std::chrono::steady_clock::now() < end) {
    auto frame = decoder.waitNewer(last_sequence, 200ms);
    if (!warm && std::chrono::steady_clock::now() >= warm_end) {
      warm = true;
      cpu_at_warm = processCpuMs();
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
  const double cpu_ms = processCpuMs() - cpu_at_warm;
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
  run.cpu_ms_per_frame = latency_ms.empty() ? 0.0 : cpu_ms / double(latency_ms.size());
  const double expected = rate_hz * seconds;
  run.sustained = double(run.decoded_seen) >= 0.95 * expected && run.camera_lost <= expected * 0.05;
  return run;
}

std::string ms(const xr::video::LatencyFigure& f) {
  return formatNumber(f.p50_ms) + " / " + formatNumber(f.p99_ms);
}

nlohmann::json runPipelineBench(const BenchContext& ctx) {
  nlohmann::json json;
  const std::vector<PipelineResolution> resolutions = {
      {"4k", 3840, 2160},
      {"1080p", 1920, 1080},
      {"4k_bayer", 3840, 2160, true},
      {"1080p_h264", 1920, 1080, false, link::VideoCodec::kH264},
      {"1080p_hevc", 1920, 1080, false, link::VideoCodec::kHevc}};
  const std::vector<double> rates = {45.0, 30.0, 22.5, 15.0, 10.0, 5.0};
  const double seconds = ctx.quick ? 2.0 : 10.0;
  const robot::video::JpegSettings settings;  // quality 90, 4:2:0: the robot's default
  Table summary({"stereo input", "rate Hz", "sustained", "p50 ms", "p99 ms", "floor ms",
                 "p50/floor", "MB/s", "sent", "dropped", "camera lost", "CPU ms/frame", "cores at 45 Hz"});
  Table stages({"stereo input", "capture→encoded", "encoded→sent", "sent→received",
                "received→decoded", "decode (1 JPEG)", "capture→decoded"});
  Table secure({"stereo input", "rate Hz", "p50 ms plain", "p50 ms CURVE", "added ms", "CPU ms/frame plain",
                "CPU ms/frame CURVE", "added CPU", "media seal+open ms/frame"});
  const PipelineKeys keys;
  if (!keys.ok) throw std::runtime_error("pipeline: cannot make the keys for the CURVE runs");
  int port = 27400;
  for (const auto& res : resolutions) {
    ctx.out << "pipeline: rendering " << res.width << "x" << res.height << " frames…\n" << std::flush;
    const int count = ctx.quick ? 2 : 4;
    auto left = prerender(res.width, res.height, 0.032, count);
    auto right = prerender(res.width, res.height, -0.032, count);
    if (res.bayer)
      for (auto* frames : {&left, &right})
        for (auto& frame : *frames) frame = mosaicOf(frame, robot::cameras::PixelFormat::kBayerRG8);
    std::size_t jpeg_bytes = 0;
    const bool predicted = res.codec != link::VideoCodec::kMjpeg;
    const double floor_ms = predicted ? videoFloorMs(left, res.codec, ctx.quick ? 2 : 5, &jpeg_bytes)
                                      : codecFloorMs(left[0], settings, ctx.quick ? 3 : 9, &jpeg_bytes);
    PipelineRun best;
    for (double rate : rates) {
      ctx.out << "pipeline: " << res.key << " at " << rate << " Hz…\n" << std::flush;
      best = runPipeline(left, right, rate, seconds, port, nullptr, res.codec);
      port += 10;
      if (best.sustained) break;
    }
    const std::string name =
        std::string("2×") + (res.bayer                                   ? std::string("4K Bayer RGGB")
                             : res.codec == link::VideoCodec::kH264 ? std::string("1080p H.264 20 Mbit/s")
                             : res.codec == link::VideoCodec::kHevc ? std::string("1080p HEVC 20 Mbit/s")
                                                                    : std::string(res.key));
    summary.addRow({name, formatNumber(best.rate_hz), best.sustained ? "yes" : "no",
                    formatNumber(best.p50_ms), formatNumber(best.p99_ms), formatNumber(floor_ms),
                    formatNumber(best.p50_ms / floor_ms), formatNumber(best.bandwidth_mb_s),
                    std::to_string(best.sent), std::to_string(best.dropped),
                    std::to_string(best.camera_lost), formatNumber(best.cpu_ms_per_frame),
                    formatNumber(best.cpu_ms_per_frame * 45.0 / 1000.0)});
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
    json["cpu_ms_per_frame_" + k] = best.cpu_ms_per_frame;
    json["encode_p50_ms_" + k] = best.decode.capture_to_encoded.p50_ms;
    // The cost of encryption depends on neither what the camera sent nor the codec (bytes per frame
    // aside, which the MJPEG rows bound from above).
    if (res.bayer || predicted) continue;

    // The cost of encryption: the same rate with and without keys, one after the other twice (so a
    // slow second does not count against one side only); the medians of the two.
    const double rate = best.sustained ? best.rate_hz : rates.back();
    std::vector<double> plain_p50, curve_p50, plain_cpu, curve_cpu;
    for (int round = 0; round < 2; ++round) {
      for (const bool keyed : {false, true}) {
        ctx.out << "pipeline: " << res.key << " at " << rate << " Hz " << (keyed ? "with CURVE keys" : "without keys")
                << "…\n" << std::flush;
        const PipelineRun run = runPipeline(left, right, rate, seconds, port, keyed ? &keys : nullptr);
        port += 10;
        (keyed ? curve_p50 : plain_p50).push_back(run.p50_ms);
        (keyed ? curve_cpu : plain_cpu).push_back(run.cpu_ms_per_frame);
      }
    }
    const double p50_plain = quantile(plain_p50, 0.5), p50_curve = quantile(curve_p50, 0.5);
    const double cpu_plain = quantile(plain_cpu, 0.5), cpu_curve = quantile(curve_cpu, 0.5);
    const double cpu_added_pct = cpu_plain > 0 ? 100.0 * (cpu_curve - cpu_plain) / cpu_plain : 0.0;
    const double seal_ms = mediaSealMs(jpeg_bytes, ctx.quick ? 5 : 21);
    secure.addRow({name, formatNumber(rate), formatNumber(p50_plain), formatNumber(p50_curve),
                   formatNumber(p50_curve - p50_plain), formatNumber(cpu_plain), formatNumber(cpu_curve),
                   formatNumber(cpu_added_pct) + " %", formatNumber(seal_ms)});
    json["media_seal_ms_per_frame_" + k] = seal_ms;
    json["secure_latency_p50_ms_" + k] = p50_curve;
    json["plain_latency_p50_ms_" + k] = p50_plain;
    json["secure_latency_added_ms_" + k] = p50_curve - p50_plain;
    json["secure_cpu_ms_per_frame_" + k] = cpu_curve;
    json["plain_cpu_ms_per_frame_" + k] = cpu_plain;
    json["secure_cpu_added_pct_" + k] = cpu_added_pct;
  }
  ctx.out << "\nEnd to end on loopback, JPEG quality 90 4:2:0 (H.264/HEVC: libx264/libx265 ultrafast zerolatency at "
          << kPipelineVideoMbit << " Mbit/s for both cameras, one thread each), " << seconds
          << " s per rate after 1 s warm-up; latency = capture → both images decoded; floor = one "
             "single-core encode + decode of one image (from a Bayer mosaic: debayer + encode + decode; H.264/HEVC: "
             "a predicted image of the same replayed sequence); CPU = "
             "this process, robot and operator ends together, per decoded stereo frame\n";
  summary.print(ctx.out);
  ctx.out << "\nPer stage, p50 / p99 ms\n";
  stages.print(ctx.out);
  ctx.out << "\nThe cost of encryption (CURVE on every socket, DESIGN.md §10): the same rate with and without "
             "keys, twice each, medians; CPU = this process (camera replay, encode, link both ends, decode) per "
             "decoded stereo frame; media seal+open = libsodium's AEAD over one stereo frame's datagrams on the UDP media "
             "path, both ends, one core. Goal: ≤ 0.5 ms and ≤ 2 % added\n";
  secure.print(ctx.out);
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
