// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench record`: what recording a session costs (issue #18). Two 2×4K stereo
///        JPEG streams at 45 Hz — one sized like the paper's (≈ 30 MB/s: the JPEG quality whose
///        image is nearest 333 kB) and ours (quality 90, 4:2:0, the robot's default) — plus robot
///        state at 100 Hz, fed to a LinkRecorder as the link's tap would, for each chunk
///        compression: the file's write rate when paced at 45 Hz and flat out, the process CPU per MB
///        recorded, frames dropped, and the disk's own sequential write speed measured in the same
///        run (4 MB writes + fsync) on the same folder.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "robot/video/jpeg_encoder.h"
#include "robot/link/link_endpoints.h"
#include "robot/record/link_recorder.h"
#include "robot/cameras/synthetic_camera.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "app/bench/prerendered_frames.h"

namespace telesphere::bench {
namespace {

namespace rec = telesphere::record;
using Clock = std::chrono::steady_clock;
using Bytes = std::shared_ptr<const std::vector<std::uint8_t>>;

std::string g_dir;
double g_seconds = 0.0;

double processCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

/// Sequential write speed of the folder's disk: `mb` MB in 4 MB writes, then fsync.
double diskWriteMbS(const std::filesystem::path& dir, int mb) {
  const auto path = dir / "disk-speed.bin";
  std::vector<char> block(4 << 20);
  std::mt19937 rng(1);
  for (char& c : block) c = static_cast<char>(rng());
  FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return 0.0;
  const auto t0 = Clock::now();
  for (int i = 0; i < mb / 4; ++i) std::fwrite(block.data(), 1, block.size(), f);
  std::fflush(f);
  fsync(fileno(f));
  std::fclose(f);
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::filesystem::remove(path);
  return double(mb / 4 * 4) / s;
}

/// JPEG pairs of one quality, cycled frame after frame (distinct images: a compressor must not
/// find the previous frame's bytes again within its window, as it would in a repeated image).
struct Stream {
  std::string name;
  int quality;
  std::vector<Bytes> left, right;
  std::size_t pairBytes(std::size_t i) const { return left[i % left.size()]->size() + right[i % right.size()]->size(); }
  double meanPairBytes() const {
    double sum = 0;
    for (std::size_t i = 0; i < left.size(); ++i) sum += double(pairBytes(i));
    return sum / double(left.size());
  }
};

struct Row {
  double input_mb_s = 0, write_mb_s = 0, max_write_mb_s = 0, cpu_per_mb_ms = 0, file_per_input = 0;
  std::uint64_t frames = 0, dropped = 0;
  std::uint64_t unaccounted = 0;  ///< messages offered that were neither written nor counted as dropped
};

link::proto::Envelope frameEnvelope(std::uint64_t sequence) {
  link::proto::Envelope e;
  auto* f = e.mutable_stereo_frame();
  f->set_sequence(sequence);
  const std::int64_t now = link::linkNowNs();
  f->mutable_left()->set_capture_ns(now - 20'000'000);
  f->mutable_right()->set_capture_ns(now - 20'000'000);
  f->mutable_left()->set_width(3840);
  f->mutable_left()->set_height(2160);
  f->mutable_stamps()->set_sent_ns(now);
  e.set_sender_clock_ns(now);
  return e;
}

link::proto::Envelope stateEnvelope(std::int64_t t_ns) {
  link::proto::Envelope e;
  auto* s = e.mutable_robot_state();
  s->set_t_ns(t_ns);
  for (int j = 0; j < 6; ++j) s->add_joint_positions(0.1 * j);
  e.set_sender_clock_ns(t_ns);
  return e;
}

Row measure(const Stream& stream, rec::McapCompression compression, double seconds, int flat_out_frames,
            const std::filesystem::path& dir) {
  Row row;
  const double frame_mb = stream.meanPairBytes() * 1e-6;
  row.input_mb_s = frame_mb * 45.0;
  const auto path = (dir / "bench-record.mcap").string();
  std::string error;
  rec::LinkRecorderOptions options;
  options.mcap.compression = compression;
  // Paced: 45 stereo frames and 100 states per second, as the robot's link sends them.
  {
    auto recorder = rec::LinkRecorder::start(path, options, &error);
    if (!recorder) throw std::runtime_error(error);
    const auto t0 = Clock::now();
    const double cpu0 = processCpuS();
    const auto frame_period = std::chrono::nanoseconds(1'000'000'000 / 45);
    const auto state_period = std::chrono::milliseconds(10);
    auto next_frame = t0, next_state = t0;
    std::uint64_t sequence = 0, states = 0;
    while (Clock::now() - t0 < std::chrono::duration<double>(seconds)) {
      const auto now = Clock::now();
      if (now >= next_frame) {
        const std::size_t k = sequence % stream.left.size();
        recorder->onLinkMessage(link::LinkTap::Direction::kSent, frameEnvelope(sequence++), stream.left[k],
                                stream.right[k]);
        next_frame += frame_period;
      }
      if (now >= next_state) {
        recorder->onLinkMessage(link::LinkTap::Direction::kSent, stateEnvelope(link::linkNowNs()), nullptr, nullptr);
        ++states;
        next_state += state_period;
      }
      std::this_thread::sleep_until(std::min(next_frame, next_state));
    }
    recorder->stop();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto stats = recorder->stats();
    row.frames = sequence;
    row.dropped = stats.dropped;
    // A frame is three messages (no poses here: no /tf), a state one.
    const std::uint64_t offered = 3 * sequence + states;
    row.unaccounted = offered > stats.messages + stats.dropped ? offered - stats.messages - stats.dropped : 0;
    row.write_mb_s = double(stats.file_bytes) * 1e-6 / wall;
    const double input_mb = frame_mb * double(sequence);
    row.cpu_per_mb_ms = (processCpuS() - cpu0) * 1e3 / input_mb;
    row.file_per_input = double(stats.file_bytes) * 1e-6 / input_mb;
  }
  std::filesystem::remove(path);  // the writer never overwrites
  // Flat out: every frame queued at once, timed until the file is closed (fsync included).
  {
    options.max_queue_bytes = std::size_t(double(flat_out_frames + 8) * stream.meanPairBytes() * 2);
    auto recorder = rec::LinkRecorder::start(path, options, &error);
    if (!recorder) throw std::runtime_error(error);
    const auto t0 = Clock::now();
    for (int i = 0; i < flat_out_frames; ++i)
      recorder->onLinkMessage(link::LinkTap::Direction::kSent, frameEnvelope(std::uint64_t(i)),
                              stream.left[std::size_t(i) % stream.left.size()],
                              stream.right[std::size_t(i) % stream.right.size()]);
    recorder->stop();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    row.max_write_mb_s = double(recorder->stats().file_bytes) * 1e-6 / wall;
    row.dropped += recorder->stats().dropped;
  }
  std::filesystem::remove(path);
  return row;
}

nlohmann::json run(const BenchContext& ctx) {
  const std::filesystem::path dir = g_dir.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(g_dir);
  const double seconds = g_seconds > 0 ? g_seconds : (ctx.quick ? 1.5 : 10.0);
  const int flat_out = ctx.quick ? 20 : 180;
  const int width = ctx.quick ? 1280 : 3840, height = ctx.quick ? 720 : 2160;
  constexpr int kDistinct = 12;  // a cycle longer than zstd's window (512 kB at level 1) even in --quick
  ctx.out << "rendering " << kDistinct << " " << width << "x" << height << " stereo pairs of the default scene...\n";
  const auto lefts = prerender(width, height, 0.0, kDistinct);
  const auto rights = prerender(width, height, -0.064, kDistinct);
  robot::video::JpegEncoder encoder;
  const auto encode = [&](const robot::cameras::CameraFrame& f, int quality) {
    auto out = std::make_shared<std::vector<std::uint8_t>>();
    std::string error;
    robot::video::JpegSettings settings;
    settings.quality = quality;
    encoder.encodeRgb(f.pixels->data(), f.width, f.height, f.stride_bytes, settings, *out, &error);
    return Bytes(out);
  };
  const auto stream = [&](const std::string& name, int quality) {
    Stream s{name, quality, {}, {}};
    for (int i = 0; i < kDistinct; ++i) {
      s.left.push_back(encode(lefts[std::size_t(i)], quality));
      s.right.push_back(encode(rights[std::size_t(i)], quality));
    }
    return s;
  };
  // The paper's stream: 30 MB/s at 45 Hz = 333 kB per image (scaled by area in --quick).
  const double target_bytes = 333e3 * double(width) * height / (3840.0 * 2160.0);
  int paper_quality = 2;
  double best = 1e18;
  for (int q = 2; q <= 98; q += 2) {
    const double miss = std::abs(double(encode(lefts[0], q)->size()) - target_bytes);
    if (miss < best) {
      best = miss;
      paper_quality = q;
    }
  }
  const std::vector<Stream> streams{stream("paper-sized", paper_quality), stream("telesphere default", 90)};
  const double disk_mb_s = diskWriteMbS(dir, ctx.quick ? 64 : 512);
  ctx.out << "disk (" << dir.string() << "): " << formatNumber(disk_mb_s) << " MB/s sequential write\n\n";

  Table table({"stream", "JPEG kB (L+R)", "compression", "input MB/s", "written MB/s at 45 Hz", "flat out MB/s",
               "CPU ms/MB", "file/input", "frames", "dropped"});
  nlohmann::json rows = nlohmann::json::array();
  std::uint64_t dropped = 0;
  nlohmann::json headline;
  for (const Stream& s : streams) {
    for (const auto c : {rec::McapCompression::kNone, rec::McapCompression::kLz4, rec::McapCompression::kZstd}) {
      const Row r = measure(s, c, seconds, flat_out, dir);
      const std::string cname = c == rec::McapCompression::kNone ? "none" : std::string(rec::compressionName(c));
      table.addRow({s.name + " (q" + std::to_string(s.quality) + ")",
                    formatNumber(s.meanPairBytes() * 1e-3, 4), cname,
                    formatNumber(r.input_mb_s), formatNumber(r.write_mb_s), formatNumber(r.max_write_mb_s),
                    formatNumber(r.cpu_per_mb_ms), formatNumber(r.file_per_input), std::to_string(r.frames),
                    std::to_string(r.dropped)});
      nlohmann::json j{{"stream", s.name},          {"quality", s.quality},
                       {"jpeg_pair_bytes", s.meanPairBytes()},
                       {"compression", cname},      {"input_mb_s", r.input_mb_s},
                       {"write_mb_s", r.write_mb_s}, {"max_write_mb_s", r.max_write_mb_s},
                       {"cpu_per_mb_ms", r.cpu_per_mb_ms}, {"file_per_input", r.file_per_input},
                       {"frames", r.frames},        {"dropped", r.dropped},
                       {"unaccounted", r.unaccounted}};
      rows.push_back(j);
      dropped += r.dropped;
      if (s.name == "paper-sized" && c == rec::McapCompression::kNone) headline = j;
    }
  }
  table.print(ctx.out);
  ctx.out << "\nwritten MB/s at 45 Hz: the file's growth while paced (= input when it keeps up); flat out: "
             "frames queued at once, until the file is closed and synced. CPU: the whole process per MB of "
             "input. Disk: "
          << formatNumber(disk_mb_s) << " MB/s.\n";
  return {{"image_width", width},
          {"image_height", height},
          {"disk_write_mb_s", disk_mb_s},
          {"write_mb_s", headline["write_mb_s"]},
          {"max_write_mb_s", headline["max_write_mb_s"]},
          {"cpu_per_mb_ms", headline["cpu_per_mb_ms"]},
          {"dropped", dropped},
          {"rows", rows}};
}

}  // namespace

TELESPHERE_BENCH_TOPIC(record, BenchTopic{"record",
                                          "recording a session to MCAP: write rate vs the disk, CPU per MB, drops, "
                                          "per chunk compression",
                                          [](CLI::App& sub) {
                                            sub.add_option("--dir", g_dir, "folder to record into (default: temp)");
                                            sub.add_option("--seconds", g_seconds, "paced seconds per row");
                                          },
                                          run});

}  // namespace telesphere::bench
