// SPDX-License-Identifier: MIT
/// @brief Bayer → JPEG per image on one core (#34): through YUV planes, through RGB, and the floor.
#include "app/bench/bayer_to_jpeg_figures.h"

#include <sys/resource.h>
#include <turbojpeg.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "app/bench/bench_table.h"
#include "app/bench/cpu_time.h"
#include "robot/cameras/debayer.h"
#include "robot/cameras/debayer_yuv420.h"
#include "robot/cameras/narrow_samples.h"
#include "robot/video/jpeg_encoder.h"

namespace telesphere::bench {
namespace {

using robot::cameras::PixelFormat;

constexpr double kStereoImagesPerSecond = 90.0;  // 2 cameras × 45 Hz (the paper's rate)
constexpr int kBayerQuality = 90;

struct Mosaic {
  int width = 0, height = 0;
  PixelFormat layout = PixelFormat::kBayerRG8;
  std::vector<std::uint8_t> samples;  ///< rows width bytes apart
  std::string source;
  /// A wide sensor's words (little-endian, rows 2 · width bytes apart) and their significant bits:
  /// the file's, else `samples` scaled to 12 bits; `samples` is their narrowing.
  std::vector<std::uint8_t> wide_words;
  int wide_bits = 12;
};

/// `samples` as a `bits`-bit sensor would have given them: v · (2^bits − 1) / 255, rounded.
std::vector<std::uint8_t> widen(const std::vector<std::uint8_t>& samples, int bits) {
  const int max = (1 << bits) - 1;
  std::vector<std::uint8_t> words(2 * samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int v = (samples[i] * max * 2 + 255) / 510;
    words[2 * i] = static_cast<std::uint8_t>(v & 0xFF);
    words[2 * i + 1] = static_cast<std::uint8_t>(v >> 8);
  }
  return words;
}

PixelFormat layoutOf(const std::string& pattern) {
  if (pattern == "RGGB") return PixelFormat::kBayerRG8;
  if (pattern == "GRBG") return PixelFormat::kBayerGR8;
  if (pattern == "GBRG") return PixelFormat::kBayerGB8;
  if (pattern == "BGGR") return PixelFormat::kBayerBG8;
  throw std::runtime_error("codec: --pattern " + pattern + ": one of RGGB, BGGR, GRBG, GBRG");
}

/// What a sensor with this colour filter would have seen of the RGB image.
Mosaic sampleMosaic(const std::uint8_t* rgb, int width, int height, const std::string& pattern,
                    const std::string& source) {
  const PixelFormat layout = layoutOf(pattern);
  return {width, height, layout, robot::cameras::bayerMosaicOf(rgb, width, height, width * 3, layout),
          source + ", sampled through a " + pattern + " filter", {}, 12};
}

Mosaic loadMosaic(const BayerInputOptions& options) {
  int width = 0, height = 0;
  char x = 0;
  if (std::sscanf(options.size.c_str(), "%d%c%d", &width, &x, &height) != 3 || x != 'x' || width < 2 || height < 2)
    throw std::runtime_error("codec: --bayer needs --size WxH (at least 2x2), not '" + options.size + "'");
  const std::size_t samples = static_cast<std::size_t>(width) * height;
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(options.raw_path, ec);
  if (ec) throw std::runtime_error("codec: --bayer " + options.raw_path + ": " + ec.message());
  const bool wide = bytes == 2 * samples;
  if (bytes != samples && !wide)
    throw std::runtime_error("codec: --bayer " + options.raw_path + " has " + std::to_string(bytes) + " bytes; " +
                             options.size + " is " + std::to_string(samples) + " at 8 bits per sample, " +
                             std::to_string(2 * samples) + " at 16");
  Mosaic m{width, height, layoutOf(options.pattern), std::vector<std::uint8_t>(samples), options.raw_path, {}, 12};
  std::vector<std::uint8_t>& into = wide ? m.wide_words : m.samples;
  into.resize(bytes);
  std::ifstream file(options.raw_path, std::ios::binary);
  if (!file.read(reinterpret_cast<char*>(into.data()), static_cast<std::streamsize>(bytes)))
    throw std::runtime_error("codec: --bayer " + options.raw_path + ": cannot read");
  if (wide) {
    m.wide_bits = options.bits;
    m.source += ", " + std::to_string(options.bits) + "-bit samples";
    std::string error;
    if (!robot::cameras::narrowSamplesTo8Bits(m.wide_words.data(), width, height, 2 * width, m.wide_bits,
                                              m.samples.data(), width, &error))
      throw std::runtime_error("codec: --bayer " + options.raw_path + ": " + error);
  } else {
    m.wide_words = widen(m.samples, m.wide_bits);
  }
  return m;
}

long minorFaults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

/// One stage's cost: CPU ms per image on this thread and the page faults it caused (a fresh
/// allocation of an image's size shows as thousands of them).
struct StageCost {
  double ms = 0, faults_per_image = 0;
};

template <typename F>
StageCost measureStage(int reps, F f) {
  f();  // warm-up: buffers sized
  const long faults0 = minorFaults();
  const Rate rate = measureRate(reps, f);  // warms up once more, then times reps calls
  return {rate.ms_per_frame_cpu, static_cast<double>(minorFaults() - faults0) / (reps + 1)};
}

}  // namespace

BayerInputOptions& bayerInputOptions() {
  static BayerInputOptions options;
  return options;
}

nlohmann::json bayerToJpegFigures(const BenchContext& ctx, const std::uint8_t* rgb, int width, int height,
                                  const std::string& source) {
  const BayerInputOptions& options = bayerInputOptions();
  Mosaic mosaic = options.raw_path.empty() ? sampleMosaic(rgb, width, height, options.pattern, source)
                                           : loadMosaic(options);
  if (mosaic.wide_words.empty()) mosaic.wide_words = widen(mosaic.samples, mosaic.wide_bits);
  const int reps = ctx.quick ? 3 : 20;
  const int w = mosaic.width, h = mosaic.height;
  std::string error;
  const auto check = [&](bool ok, const char* what) {
    if (!ok) throw std::runtime_error(std::string("codec: ") + what + ": " + error);
  };

  robot::video::JpegSettings settings;
  settings.quality = kBayerQuality;
  settings.subsampling = robot::video::ChromaSubsampling::k420;
  robot::cameras::DebayerToYuv420 to_planes;
  robot::cameras::Yuv420Image planes;
  robot::video::JpegEncoder encoder;
  std::vector<std::uint8_t> jpeg_planes, jpeg_rgb, rgb_image;

  std::vector<std::uint8_t> narrowed(mosaic.samples.size());
  const StageCost narrow = measureStage(reps, [&] {
    check(robot::cameras::narrowSamplesTo8Bits(mosaic.wide_words.data(), w, h, 2 * w, mosaic.wide_bits, narrowed.data(),
                                               w, &error),
          "narrow samples");
  });
  const StageCost debayer = measureStage(reps, [&] {
    check(to_planes.convert(mosaic.samples.data(), w, h, w, mosaic.layout, planes, &error), "debayer to YUV");
  });
  const StageCost encode_planes = measureStage(reps, [&] {
    check(encoder.encodeYuv420(planes, settings, jpeg_planes, &error), "encode from planes");
  });
  const StageCost bayer_to_jpeg = measureStage(reps, [&] {
    check(to_planes.convert(mosaic.samples.data(), w, h, w, mosaic.layout, planes, &error), "debayer to YUV");
    check(encoder.encodeYuv420(planes, settings, jpeg_planes, &error), "encode from planes");
  });
  // Today's path: a packed RGB image, converted to YCbCr and downsampled inside the encoder.
  const StageCost via_rgb = measureStage(reps, [&] {
    check(robot::cameras::debayerBilinear(mosaic.samples.data(), w, h, w, mosaic.layout, rgb_image, &error),
          "debayer to RGB");
    check(encoder.encodeRgb(rgb_image.data(), w, h, w * 3, settings, jpeg_rgb, &error), "encode RGB");
  });

  // The floor: TurboJPEG's own encoder from the same planes, same quality, its fast DCT as ours.
  tjhandle tj = tjInitCompress();
  if (!tj) throw std::runtime_error("codec: tjInitCompress failed");
  const unsigned char* plane_pointers[3] = {planes.y.data(), planes.u.data(), planes.v.data()};
  const int strides[3] = {w, planes.chromaWidth(), planes.chromaWidth()};
  std::vector<unsigned char> floor_jpeg(tjBufSize(w, h, TJSAMP_420));
  unsigned long floor_bytes = 0;
  const StageCost floor = measureStage(reps, [&] {
    unsigned char* out = floor_jpeg.data();
    floor_bytes = floor_jpeg.size();
    if (tjCompressFromYUVPlanes(tj, plane_pointers, w, strides, h, TJSAMP_420, &out, &floor_bytes, kBayerQuality,
                                TJFLAG_FASTDCT | TJFLAG_NOREALLOC) != 0)
      throw std::runtime_error(std::string("codec: tjCompressFromYUVPlanes: ") + tjGetErrorStr2(tj));
  });
  tjDestroy(tj);
  const bool same_bytes = floor_bytes == jpeg_planes.size() &&
                          std::equal(jpeg_planes.begin(), jpeg_planes.end(), floor_jpeg.begin());

  const double ratio = bayer_to_jpeg.ms / floor.ms;
  Table table({"stage (q90 4:2:0, one core)", "ms/image (CPU)", "x floor", "page faults/image", "bytes"});
  const auto row = [&](const std::string& name, const StageCost& c, const std::string& bytes) {
    table.addRow({name, formatNumber(c.ms), formatNumber(c.ms / floor.ms), formatNumber(c.faults_per_image), bytes});
  };
  row("floor: TurboJPEG from the planes", floor, std::to_string(floor_bytes));
  row("encodeYuv420 from the planes", encode_planes, std::to_string(jpeg_planes.size()));
  row("debayer to YUV 4:2:0 planes", debayer, "-");
  row("Bayer -> JPEG through planes", bayer_to_jpeg, std::to_string(jpeg_planes.size()));
  row("Bayer -> JPEG through RGB (today)", via_rgb, std::to_string(jpeg_rgb.size()));
  row("narrow " + std::to_string(mosaic.wide_bits) + "-bit samples to 8 (wide sensors, at capture)", narrow, "-");
  auto& out = ctx.out;
  out << "\nBayer to JPEG, " << w << "x" << h << " mosaic (" << mosaic.source << "), " << reps << " repetitions:\n";
  table.print(out);
  const double cores_planes = kStereoImagesPerSecond * bayer_to_jpeg.ms / 1e3;
  const double cores_rgb = kStereoImagesPerSecond * via_rgb.ms / 1e3;
  out << "ratio to the floor " << formatNumber(ratio) << " (goal <= 1.25); ours from planes "
      << (same_bytes ? "writes TurboJPEG's bytes" : "differs from TurboJPEG's bytes") << "\n"
      << "2 cameras x 45 Hz of these images need " << formatNumber(cores_planes) << " cores through planes, "
      << formatNumber(cores_rgb) << " through RGB (CPU time of one core each, encode included); a "
      << mosaic.wide_bits << "-bit sensor adds " << formatNumber(kStereoImagesPerSecond * narrow.ms / 1e3)
      << " for narrowing at capture\n";

  const auto stage = [](const StageCost& c) { return nlohmann::json{{"ms", c.ms}, {"page_faults_per_image", c.faults_per_image}}; };
  return {{"bayer_to_jpeg_ms", bayer_to_jpeg.ms},
          {"floor_ms", floor.ms},
          {"ratio", ratio},
          {"bayer_to_jpeg",
           {{"width", w},
            {"height", h},
            {"source", mosaic.source},
            {"quality", kBayerQuality},
            {"debayer_to_planes", stage(debayer)},
            {"encode_from_planes", stage(encode_planes)},
            {"through_planes", stage(bayer_to_jpeg)},
            {"through_rgb", stage(via_rgb)},
            {"narrow_wide_samples", stage(narrow)},
            {"wide_sample_bits", mosaic.wide_bits},
            {"floor", stage(floor)},
            {"same_bytes_as_floor", same_bytes},
            {"cores_for_2_cameras_at_45_hz", cores_planes},
            {"cores_for_2_cameras_at_45_hz_through_rgb", cores_rgb}}}};
}

}  // namespace telesphere::bench
