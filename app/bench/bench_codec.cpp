// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench codec`: the video path's JPEG figures (DESIGN.md §4) on a 4K image
///        (a deterministic synthetic scene, or --image PNG/PPM/BMP): encode and decode (to YUV
///        planes) frames/s per core, next to `tjbench` on the same image; decode frames/s of the
///        DecodePool on all cores against the goal of 2 cameras × 45 Hz; and the quality knob
///        (50…95, 4:2:0 vs 4:4:4) against size, PSNR and encode/decode time; a camera's Bayer
///        mosaic to JPEG against the encoder's floor (bayer_to_jpeg_figures.h); MJPEG, H.264 and
///        HEVC at the link's rates (codec_comparison.h).
#include <turbojpeg.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <future>
#include <optional>
#include <random>
#include <stdexcept>
#include <thread>
#include <unistd.h>
#include <vector>

#include "robot/video/jpeg_encoder.h"
#include "shaders/png_io.h"
#include "app/bench/bayer_to_jpeg_figures.h"
#include "app/bench/bench_table.h"
#include "app/bench/codec_comparison.h"
#include "app/bench/cpu_time.h"
#include "app/bench/bench_topic.h"
#include "xr/video/decode_pool.h"
#include "xr/video/jpeg_decoder.h"

namespace telesphere::bench {
namespace {

constexpr int kCodecWidth = 3840, kCodecHeight = 2160;
constexpr double kCodecGoalFps = 90.0;  // 2 cameras × 45 Hz

std::string& codecImagePath() {
  static std::string path;
  return path;
}

struct CodecImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< rows top first
  std::string source;
};

/// Smooth value noise in [0, 1]: a seeded lattice with `cell` px spacing, smoothstep-interpolated.
class CodecValueNoise {
 public:
  CodecValueNoise(int width, int height, int cell, std::uint32_t seed)
      : cell_(cell), nx_(width / cell + 2), ny_(height / cell + 2), lattice_(static_cast<std::size_t>(nx_) * ny_) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (auto& v : lattice_) v = u(rng);
  }
  float at(int x, int y) const {
    const int i = x / cell_, j = y / cell_;
    const float fx = static_cast<float>(x % cell_) / cell_, fy = static_cast<float>(y % cell_) / cell_;
    const float sx = fx * fx * (3 - 2 * fx), sy = fy * fy * (3 - 2 * fy);
    const auto l = [&](int a, int b) { return lattice_[static_cast<std::size_t>(b) * nx_ + a]; };
    const float top = l(i, j) + sx * (l(i + 1, j) - l(i, j));
    const float bottom = l(i, j + 1) + sx * (l(i + 1, j + 1) - l(i, j + 1));
    return top + sy * (bottom - top);
  }

 private:
  int cell_, nx_, ny_;
  std::vector<float> lattice_;
};

/// A natural-looking scene, the same every run: sky gradient with clouds, hills with multi-scale
/// texture, buildings with sharp edges and lit windows, cables, and a little sensor grain.
CodecImage syntheticImage(int w, int h) {
  CodecImage img{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 3), "synthetic"};
  const CodecValueNoise n256(w, h, 256, 1), n64(w, h, 64, 2), n16(w, h, 16, 3), n4(w, h, 4, 4);
  std::mt19937 rng(5);
  struct Building {
    int x0, x1, top;
    float r, g, b;
  };
  std::vector<Building> buildings;
  for (int x = 0; x < w;) {
    std::uniform_int_distribution<int> width_px(w / 40, w / 12), top(h * 3 / 10, h * 6 / 10), gap(0, w / 30);
    std::uniform_real_distribution<float> shade(0.25f, 0.8f);
    const int x0 = x + gap(rng), x1 = std::min(w, x0 + width_px(rng));
    const float s = shade(rng);
    buildings.push_back({x0, x1, top(rng), s, s * 0.95f, s * 0.9f});
    x = x1;
  }
  std::uniform_int_distribution<int> grain(-3, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float fine = 0.5f * n16.at(x, y) + 0.5f * n4.at(x, y);
      const float coarse = 0.6f * n256.at(x, y) + 0.4f * n64.at(x, y);
      const float horizon = h * (0.62f + 0.08f * std::sin(x * 0.0021f) + 0.05f * (n256.at(x, 0) - 0.5f));
      float r, g, b;
      if (y < horizon) {  // sky with clouds
        const float t = static_cast<float>(y) / h;
        const float cloud = std::clamp((coarse - 0.55f) * 3.0f, 0.0f, 1.0f);
        r = 0.35f + 0.4f * t + 0.5f * cloud;
        g = 0.55f + 0.3f * t + 0.4f * cloud;
        b = 0.95f - 0.1f * t + 0.05f * cloud;
      } else {  // grass and soil
        r = 0.25f + 0.25f * coarse + 0.2f * fine;
        g = 0.35f + 0.25f * coarse + 0.25f * fine;
        b = 0.12f + 0.1f * fine;
      }
      for (const auto& bd : buildings) {
        if (x < bd.x0 || x >= bd.x1 || y < bd.top || y >= horizon + 40) continue;
        const int wx = (x - bd.x0) % 48, wy = (y - bd.top) % 64;
        const bool window = wx > 10 && wx < 34 && wy > 12 && wy < 44 && x > bd.x0 + 8 && x < bd.x1 - 8;
        const float lit = n64.at(x - wx, y - wy) > 0.5f ? 1.0f : 0.3f;
        r = window ? 0.9f * lit : bd.r + 0.08f * fine;
        g = window ? 0.8f * lit : bd.g + 0.08f * fine;
        b = window ? 0.5f * lit : bd.b + 0.08f * fine;
      }
      // Two sagging cables, 3 px thick.
      for (int k = 0; k < 2; ++k) {
        const float cx = static_cast<float>(x) / w - 0.5f;
        const float cy = h * (0.18f + 0.1f * k) + h * 0.15f * cx * cx;
        if (std::abs(y - cy) < 1.5f) r = g = b = 0.08f;
      }
      const std::size_t i = (static_cast<std::size_t>(y) * w + x) * 3;
      const float c[3] = {r, g, b};
      for (int ch = 0; ch < 3; ++ch)
        img.rgb[i + static_cast<std::size_t>(ch)] =
            static_cast<std::uint8_t>(std::clamp(static_cast<int>(c[ch] * 255.0f) + grain(rng), 0, 255));
    }
  }
  return img;
}

std::optional<CodecImage> loadImage(const std::string& path, std::string* error) {
  CodecImage img;
  img.source = path;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".png" || ext == ".PNG") {
    auto png = gl::readPng(path, error);
    if (!png) return std::nullopt;
    img.width = png->width;
    img.height = png->height;
    img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
    for (std::size_t i = 0, n = static_cast<std::size_t>(img.width) * img.height; i < n; ++i)
      std::copy_n(png->rgba.begin() + static_cast<std::ptrdiff_t>(4 * i), 3, img.rgb.begin() + static_cast<std::ptrdiff_t>(3 * i));
    return img;
  }
  int w = 0, h = 0, format = TJPF_RGB;
  unsigned char* data = tjLoadImage(path.c_str(), &w, 1, &h, &format, 0);  // PPM, BMP
  if (!data) {
    *error = path + ": " + tjGetErrorStr2(nullptr) + " (PNG, PPM or BMP expected)";
    return std::nullopt;
  }
  img.width = w;
  img.height = h;
  img.rgb.assign(data, data + static_cast<std::size_t>(w) * h * 3);
  tjFree(data);
  return img;
}

robot::video::JpegSettings settingsFor(int quality, bool chroma444) {
  robot::video::JpegSettings s;
  s.quality = quality;
  s.subsampling = chroma444 ? robot::video::ChromaSubsampling::k444 : robot::video::ChromaSubsampling::k420;
  return s;
}

struct TjbenchFigures {
  double compress_fps = 0, decompress_yuv_fps = 0, decompress_rgb_fps = 0;
};

/// Runs tjbench (single-threaded, -fastdct like our encoder and decoder) on a PPM of the image.
std::optional<TjbenchFigures> runTjbench(const CodecImage& img, bool quick, std::string* why) {
  const char* candidates[] = {"/usr/bin/tjbench", "/usr/local/bin/tjbench"};
  std::string tjbench;
  for (const char* c : candidates)
    if (access(c, X_OK) == 0) tjbench = c;
  if (tjbench.empty()) {
    *why = "tjbench not found (Debian: apt install libjpeg-turbo-progs)";
    return std::nullopt;
  }
  const auto ppm = std::filesystem::temp_directory_path() /
                   ("telesphere-bench-codec-" + std::to_string(getpid()) + ".ppm");
  if (tjSaveImage(ppm.c_str(), const_cast<unsigned char*>(img.rgb.data()), img.width, 0, img.height,
                  TJPF_RGB, 0) != 0) {
    *why = std::string("could not write ") + ppm.string() + ": " + tjGetErrorStr2(nullptr);
    return std::nullopt;
  }
  const std::string timing = quick ? " -benchtime 0.5 -warmup 0.1" : " -benchtime 3 -warmup 0.5";
  const auto run = [&](const std::string& extra) {
    const std::string cmd = tjbench + " " + ppm.string() + " 90 -subsamp 420 -fastdct -rgb -nowrite" +
                            timing + extra + " 2>&1";
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
      char buf[4096];
      std::size_t n;
      while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
      pclose(p);
    }
    return out;
  };
  const auto fps = [](const std::string& out, const std::string& label) {
    // "<label>  --> Frame rate:   12.34 fps" (std::regex trips GCC 12's -Wmaybe-uninitialized)
    const auto at = out.find(label);
    if (at == std::string::npos) return 0.0;
    const auto rate = out.find("Frame rate:", at);
    if (rate == std::string::npos || out.find("-->", at) > rate) return 0.0;
    return std::strtod(out.c_str() + rate + std::string("Frame rate:").size(), nullptr);
  };
  const std::string plain = run(""), yuv = run(" -yuv");
  std::filesystem::remove(ppm);
  TjbenchFigures f;
  f.compress_fps = fps(plain, "Compress");
  f.decompress_rgb_fps = fps(plain, "Decompress");
  f.decompress_yuv_fps = fps(yuv, "Decomp to YUV");
  if (f.compress_fps <= 0 || f.decompress_yuv_fps <= 0) {
    *why = "could not parse tjbench's output: " + plain.substr(0, 300);
    return std::nullopt;
  }
  return f;
}

/// PSNR (dB) of b against a over n bytes; 99 when identical.
double psnr(const std::uint8_t* a, const std::uint8_t* b, std::size_t n) {
  double se = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = static_cast<double>(a[i]) - b[i];
    se += d * d;
  }
  return se == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 * static_cast<double>(n) / se);
}

/// JFIF luma of the original RGB, rounded (what a lossless encoder would store as Y).
std::vector<std::uint8_t> lumaOf(const CodecImage& img) {
  std::vector<std::uint8_t> y(static_cast<std::size_t>(img.width) * img.height);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const std::uint8_t* p = &img.rgb[3 * i];
    y[i] = static_cast<std::uint8_t>(std::lround(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]));
  }
  return y;
}

nlohmann::json runCodec(const BenchContext& ctx) {
  auto& out = ctx.out;
  CodecImage img;
  if (!codecImagePath().empty()) {
    std::string error;
    auto loaded = loadImage(codecImagePath(), &error);
    if (!loaded) throw std::runtime_error("codec: " + error);
    img = std::move(*loaded);
  } else {
    img = syntheticImage(kCodecWidth, kCodecHeight);
  }
  const int reps = ctx.quick ? 3 : 20;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  out << "codec: " << img.width << "x" << img.height << " image (" << img.source << "), " << cores
      << " cores, " << reps << " repetitions\n";

  // Encode and decode on one core, at the operating point: quality 90, 4:2:0.
  robot::video::JpegEncoder encoder;
  xr::video::JpegDecoder decoder;
  std::vector<std::uint8_t> jpeg;
  std::string error;
  const auto encode = [&](int quality, bool c444) {
    if (!encoder.encodeRgb(img.rgb.data(), img.width, img.height, img.width * 3, settingsFor(quality, c444), jpeg, &error))
      throw std::runtime_error("codec: encode: " + error);
  };
  const Rate enc = measureRate(reps, [&] { encode(90, false); });
  const std::vector<std::uint8_t> jpeg90 = jpeg;
  xr::render::YuvPlanes planes;
  const Rate dec = measureRate(reps, [&] {
    if (decoder.decode(jpeg90, img.width, img.height, 8192, planes, &error) != xr::video::JpegDecodeError::kNone)
      throw std::runtime_error("codec: decode: " + error);
  });

  // The pool on all cores: keep every worker busy with the same frame.
  xr::video::DecodePool pool;
  const int pool_jobs = pool.threads() * (ctx.quick ? 3 : 20);
  const auto pool_batch = [&](int n) {
    std::vector<std::future<xr::video::DecodeResult>> futures;
    for (int i = 0; i < n; ++i) {
      xr::video::DecodeJob job;
      job.jpeg = jpeg90;
      job.expected_width = img.width;
      job.expected_height = img.height;
      futures.push_back(pool.submit(job));
    }
    for (auto& f : futures)
      if (f.get().error != xr::video::JpegDecodeError::kNone) throw std::runtime_error("codec: pool decode failed");
  };
  pool_batch(pool.threads());  // warm-up
  const double pw0 = wallSeconds(), pc0 = processCpuSeconds();
  pool_batch(pool_jobs);
  const double pool_wall = wallSeconds() - pw0, pool_cpu = processCpuSeconds() - pc0;
  const double pool_fps = pool_jobs / pool_wall;

  std::string tj_why;
  const auto tj = runTjbench(img, ctx.quick, &tj_why);

  Table speed({"stage (q90 4:2:0)", "fps/core (CPU time)", "ms/frame (CPU)", "fps (wall)", "tjbench fps (wall)", "ours/tjbench (wall)"});
  const auto ratio = [](double a, double b) { return b > 0 ? formatNumber(a / b) : std::string("-"); };
  speed.addRow({"encode RGB to JPEG", formatNumber(enc.fps_cpu), formatNumber(enc.ms_per_frame_cpu),
                formatNumber(enc.fps_wall), tj ? formatNumber(tj->compress_fps) : "-",
                tj ? ratio(enc.fps_wall, tj->compress_fps) : "-"});
  speed.addRow({"decode JPEG to YUV planes", formatNumber(dec.fps_cpu), formatNumber(dec.ms_per_frame_cpu),
                formatNumber(dec.fps_wall), tj ? formatNumber(tj->decompress_yuv_fps) : "-",
                tj ? ratio(dec.fps_wall, tj->decompress_yuv_fps) : "-"});
  speed.addRow({"decode pool, " + std::to_string(pool.threads()) + " threads", formatNumber(pool_jobs / pool_cpu),
                formatNumber(1e3 * pool_cpu / pool_jobs), formatNumber(pool_fps), "-", "-"});
  out << "\nJPEG speed, " << jpeg90.size() << " bytes per frame:\n";
  speed.print(out);
  if (!tj) out << "tjbench skipped: " << tj_why << "\n";
  else out << "(tjbench decompress to RGB, for reference: " << formatNumber(tj->decompress_rgb_fps) << " fps)\n";
  out << "goal " << kCodecGoalFps << " decoded frames/s (2 × 45 Hz): pool reaches " << formatNumber(pool_fps)
      << " (" << formatNumber(100.0 * pool_fps / kCodecGoalFps) << " %); at the measured CPU cost it needs "
      << formatNumber(kCodecGoalFps / dec.fps_cpu) << " cores\n";

  // Quality knob: size, fidelity and time.
  const std::vector<int> qualities = ctx.quick ? std::vector<int>{50, 90} : std::vector<int>{50, 60, 70, 80, 90, 95};
  const int qreps = ctx.quick ? 1 : 5;
  const std::vector<std::uint8_t> luma = lumaOf(img);
  tjhandle tj_rgb = tjInitDecompress();
  std::vector<std::uint8_t> rgb_back(img.rgb.size());
  Table knob({"quality", "chroma", "bytes", "bits/px", "PSNR Y (dB)", "PSNR RGB (dB)", "encode ms (CPU)", "decode ms (CPU)"});
  nlohmann::json knob_json = nlohmann::json::array();
  for (bool c444 : {false, true}) {
    for (int q : qualities) {
      const Rate e = measureRate(qreps, [&] { encode(q, c444); });
      const Rate d = measureRate(qreps, [&] {
        if (decoder.decode(jpeg, img.width, img.height, 8192, planes, &error) != xr::video::JpegDecodeError::kNone)
          throw std::runtime_error("codec: decode: " + error);
      });
      const double psnr_y = psnr(luma.data(), planes.y.data(), luma.size());
      if (tjDecompress2(tj_rgb, jpeg.data(), jpeg.size(), rgb_back.data(), img.width, 0, img.height, TJPF_RGB,
                        TJFLAG_FASTDCT) != 0)
        throw std::runtime_error(std::string("codec: tjDecompress2: ") + tjGetErrorStr2(tj_rgb));
      const double psnr_rgb = psnr(img.rgb.data(), rgb_back.data(), img.rgb.size());
      const double bpp = 8.0 * static_cast<double>(jpeg.size()) / (static_cast<double>(img.width) * img.height);
      const char* chroma = c444 ? "4:4:4" : "4:2:0";
      knob.addRow({std::to_string(q), chroma, std::to_string(jpeg.size()), formatNumber(bpp), formatNumber(psnr_y, 4),
                   formatNumber(psnr_rgb, 4), formatNumber(e.ms_per_frame_cpu), formatNumber(d.ms_per_frame_cpu)});
      knob_json.push_back({{"quality", q}, {"chroma", chroma}, {"bytes", jpeg.size()}, {"bits_per_px", bpp},
                           {"psnr_y_db", psnr_y}, {"psnr_rgb_db", psnr_rgb}, {"encode_ms", e.ms_per_frame_cpu},
                           {"decode_ms", d.ms_per_frame_cpu}});
    }
  }
  tjDestroy(tj_rgb);
  out << "\nQuality knob (PSNR against the uncompressed frame; Y against its JFIF luma, RGB after "
         "tjDecompress2 with fancy upsampling):\n";
  knob.print(out);

  // Restart markers: the Internet link slices a frame into bands along them (DESIGN.md §9). A
  // shorter band costs less when a packet is lost and a few bytes more per marker.
  Table restarts({"restart every", "bands", "bytes", "overhead (bytes)", "overhead (%)", "bytes/band",
                  "image rows/band", "encode ms (CPU)", "decode ms (CPU)"});
  nlohmann::json restart_json = nlohmann::json::array();
  const std::size_t plain_bytes = jpeg90.size();
  const int mcu_rows = (img.height + 15) / 16;
  for (int every : {0, 1, 2, 4, 8}) {
    robot::video::JpegSettings s = settingsFor(90, false);
    s.restart_mcu_rows = every;
    const Rate e = measureRate(qreps, [&] {
      if (!encoder.encodeRgb(img.rgb.data(), img.width, img.height, img.width * 3, s, jpeg, &error))
        throw std::runtime_error("codec: encode: " + error);
    });
    const Rate d = measureRate(qreps, [&] {
      if (decoder.decode(jpeg, img.width, img.height, 8192, planes, &error) != xr::video::JpegDecodeError::kNone)
        throw std::runtime_error("codec: decode: " + error);
    });
    const int bands = every == 0 ? 1 : (mcu_rows + every - 1) / every;
    const double overhead = static_cast<double>(jpeg.size()) - static_cast<double>(plain_bytes);
    restarts.addRow({every == 0 ? std::string("never") : std::to_string(every) + " MCU rows", std::to_string(bands),
                     std::to_string(jpeg.size()), formatNumber(overhead),
                     formatNumber(100.0 * overhead / static_cast<double>(plain_bytes), 3),
                     formatNumber(static_cast<double>(jpeg.size()) / bands),
                     std::to_string(every == 0 ? img.height : 16 * every), formatNumber(e.ms_per_frame_cpu),
                     formatNumber(d.ms_per_frame_cpu)});
    restart_json.push_back({{"restart_mcu_rows", every}, {"bands", bands}, {"bytes", jpeg.size()},
                            {"overhead_bytes", overhead}, {"encode_ms", e.ms_per_frame_cpu},
                            {"decode_ms", d.ms_per_frame_cpu}});
  }
  out << "\nRestart markers (q90 4:2:0; a band is what one lost packet costs the Internet link):\n";
  restarts.print(out);

  // A camera's raw mosaic to JPEG, through planes and through RGB, against the floor (#34).
  const nlohmann::json bayer = bayerToJpegFigures(ctx, img.rgb.data(), img.width, img.height, img.source);
  // MJPEG, H.264 and HEVC at the link's rates on a moving sequence (#34).
  const nlohmann::json codecs = codecComparison(ctx, img.rgb.data(), img.width, img.height);

  nlohmann::json j = {{"image", {{"width", img.width}, {"height", img.height}, {"source", img.source}}},
                      {"cores", cores},
                      {"jpeg_bytes_q90_420", jpeg90.size()},
                      {"encode_fps_per_core", enc.fps_cpu},
                      {"encode_fps_wall", enc.fps_wall},
                      {"decode_fps_per_core", dec.fps_cpu},
                      {"decode_fps_wall", dec.fps_wall},
                      {"decode_fps_pool", pool_fps},
                      {"pool_threads", pool.threads()},
                      {"pool_cpu_s_per_frame", pool_cpu / pool_jobs},
                      {"goal_decode_fps", kCodecGoalFps},
                      {"quality_table", knob_json},
                      {"restart_table", restart_json}};
  j.update(bayer);
  j.update(codecs);
  if (tj) {
    j["tjbench"] = {{"compress_fps", tj->compress_fps},
                    {"decompress_to_yuv_fps", tj->decompress_yuv_fps},
                    {"decompress_to_rgb_fps", tj->decompress_rgb_fps},
                    {"encode_ratio", enc.fps_wall / tj->compress_fps},
                    {"decode_ratio", dec.fps_wall / tj->decompress_yuv_fps}};
  } else {
    j["tjbench"] = {{"skipped", tj_why}};
  }
  return j;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(codec, telesphere::bench::BenchTopic{
                                  "codec",
                                  "JPEG encode/decode fps per core vs tjbench, decode pool fps, quality knob, Bayer to JPEG vs the floor",
                                  [](CLI::App& sub) {
                                    sub.add_option("--image", telesphere::bench::codecImagePath(),
                                                   "image to use (PNG, PPM, BMP) instead of the synthetic 4K scene");
                                    auto& bayer = telesphere::bench::bayerInputOptions();
                                    sub.add_option("--bayer", bayer.raw_path,
                                                   "raw Bayer mosaic for the Bayer -> JPEG figures (needs --size): 8-bit "
                                                   "samples, or 16-bit little-endian words (see --bits)");
                                    sub.add_option("--bits", bayer.bits,
                                                   "significant bits of a 16-bit --bayer file's samples, 9-16 (default 16)")
                                        ->check(CLI::Range(9, 16));
                                    sub.add_option("--size", bayer.size, "WxH of the --bayer file");
                                    sub.add_option("--pattern", bayer.pattern,
                                                   "colour filter: RGGB, BGGR, GRBG or GBRG (default RGGB)");
                                  },
                                  telesphere::bench::runCodec});
