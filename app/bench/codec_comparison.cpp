// SPDX-License-Identifier: MIT
/// @brief MJPEG, H.264 and HEVC at the same rates on the same moving sequence (#34).
#include "app/bench/codec_comparison.h"

#include <opencv2/core.hpp>
#include <opencv2/quality/qualityssim.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "app/bench/bench_table.h"
#include "app/bench/cpu_time.h"
#include "robot/video/av_video_encoder.h"
#include "robot/video/frame_to_yuv420.h"
#include "robot/video/jpeg_encoder.h"
#include "xr/video/av_video_decoder.h"
#include "xr/video/jpeg_decoder.h"

namespace telesphere::bench {
namespace {

using robot::cameras::Yuv420Image;

constexpr int kComparisonFps = 45;
constexpr int kPanPxPerImage = 4;  // a head turning at ~10°/s seen through a 4K fisheye lens
constexpr int kKeyFrameInterval = 90;

/// The image as YUV 4:2:0 planes (what the robot's H.264/HEVC encoders and a JPEG of it take).
Yuv420Image planesOf(std::vector<std::uint8_t> rgb, int width, int height) {
  robot::cameras::CameraFrame frame;
  frame.format = robot::cameras::PixelFormat::kRgb8;
  frame.width = width;
  frame.height = height;
  frame.stride_bytes = width * 3;
  frame.pixels = std::make_shared<const std::vector<std::uint8_t>>(std::move(rgb));
  Yuv420Image planes;
  std::string error;
  if (!robot::video::FrameToYuv420().convert(frame, planes, &error)) throw std::runtime_error("codec: " + error);
  return planes;
}

/// The RGB image at half its size (2 × 2 means).
std::vector<std::uint8_t> halved(const std::uint8_t* rgb, int width, int height) {
  const int w = width / 2, h = height / 2;
  std::vector<std::uint8_t> out(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const auto at = [&](int dx, int dy) {
          return rgb[(static_cast<std::size_t>(2 * y + dy) * width + 2 * x + dx) * 3 + c];
        };
        out[(static_cast<std::size_t>(y) * w + x) * 3 + c] =
            static_cast<std::uint8_t>((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1) + 2) / 4);
      }
  return out;
}

/// Image t of the sequence: the base panned t × 4 px (mirrored at the edge) with fresh sensor
/// noise (±2 in Y, seeded by t): nothing of the noise is predictable from the image before.
void sequenceImage(const Yuv420Image& base, int t, Yuv420Image& out) {
  out.resize(base.width, base.height);
  const auto mirror = [](int x, int n) {
    x %= 2 * n;
    return x < n ? x : 2 * n - 1 - x;
  };
  std::mt19937 rng(static_cast<std::uint32_t>(1000 + t));
  std::uniform_int_distribution<int> noise(-2, 2);
  for (int y = 0; y < base.height; ++y) {
    const std::uint8_t* from = base.y.data() + static_cast<std::size_t>(y) * base.width;
    std::uint8_t* to = out.y.data() + static_cast<std::size_t>(y) * base.width;
    for (int x = 0; x < base.width; ++x)
      to[x] = static_cast<std::uint8_t>(std::clamp(from[mirror(x + kPanPxPerImage * t, base.width)] + noise(rng), 0, 255));
  }
  const int cw = base.chromaWidth();
  for (int y = 0; y < base.chromaHeight(); ++y)
    for (int x = 0; x < cw; ++x) {
      const std::size_t from = static_cast<std::size_t>(y) * cw + mirror(x + kPanPxPerImage / 2 * t, cw);
      out.u[static_cast<std::size_t>(y) * cw + x] = base.u[from];
      out.v[static_cast<std::size_t>(y) * cw + x] = base.v[from];
    }
}

double psnrY(const Yuv420Image& source, const xr::render::YuvPlanes& decoded) {
  const auto y = decoded.yPlane();
  double se = 0;
  for (std::size_t i = 0; i < source.y.size(); ++i) {
    const double d = double(source.y[i]) - double(y[i]);
    se += d * d;
  }
  return se == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 * double(source.y.size()) / se);
}

double ssimY(const Yuv420Image& source, const xr::render::YuvPlanes& decoded) {
  const cv::Mat a(source.height, source.width, CV_8UC1, const_cast<std::uint8_t*>(source.y.data()));
  const cv::Mat b(decoded.height, decoded.width, CV_8UC1, const_cast<std::uint8_t*>(decoded.yPlane().data()));
  return cv::quality::QualitySSIM::compute(a, b, cv::noArray())[0];
}

struct CodecRun {
  std::string codec, backend;
  double rate_mbit = 0;
  double bytes_per_stereo_frame = 0, ssim = 0, psnr_db = 0, encode_ms = 0, decode_ms = 0, latency_frames = 0;
  int mjpeg_quality = 0;  ///< the quality that fit the rate (MJPEG only)
  bool fits_rate = true;  ///< MJPEG: false when even quality 1 is over the rate
};

/// One camera of the pair at half the link's rate (the other is alike): its bytes doubled for the
/// stereo frame, its quality and times per image.
CodecRun runCodecAtRate(link::VideoCodec codec, double rate_mbit, const Yuv420Image& base, int frames) {
  CodecRun run;
  run.codec = link::videoCodecName(codec);
  run.rate_mbit = rate_mbit;
  const double camera_bps = rate_mbit * 1e6 / 2.0;
  const double budget_bytes = camera_bps / 8.0 / kComparisonFps;
  std::string error;
  Yuv420Image image;
  xr::render::YuvPlanes decoded;
  double bytes = 0, encode_s = 0, decode_s = 0, ssim = 0, psnr = 0;
  int measured = 0, late = 0;
  const auto score = [&](int t) {
    if (t % 3 != 2) return;  // every third image (SSIM at 4K is slow)
    ssim += ssimY(image, decoded);
    psnr += psnrY(image, decoded);
    ++measured;
  };

  if (codec == link::VideoCodec::kMjpeg) {
    robot::video::JpegEncoder encoder;
    xr::video::JpegDecoder decoder;
    std::vector<std::uint8_t> jpeg;
    robot::video::JpegSettings settings;
    sequenceImage(base, 0, image);
    // The highest quality whose first image fits the budget (the rate controller's choice).
    int low = 1, high = 100;  // the answer lies in [low, high]
    while (low < high) {
      settings.quality = (low + high + 1) / 2;
      if (!encoder.encodeYuv420(image, settings, jpeg, &error)) throw std::runtime_error("codec: " + error);
      if (static_cast<double>(jpeg.size()) <= budget_bytes)
        low = settings.quality;
      else
        high = settings.quality - 1;
    }
    settings.quality = low;
    run.mjpeg_quality = settings.quality;
    run.backend = "libjpeg-turbo q" + std::to_string(settings.quality);
    for (int t = 0; t < frames; ++t) {
      sequenceImage(base, t, image);
      const double c0 = threadCpuSeconds();
      if (!encoder.encodeYuv420(image, settings, jpeg, &error)) throw std::runtime_error("codec: " + error);
      const double c1 = threadCpuSeconds();
      if (decoder.decode(jpeg, image.width, image.height, 8192, decoded, &error) != xr::video::JpegDecodeError::kNone)
        throw std::runtime_error("codec: JPEG decode: " + error);
      decode_s += threadCpuSeconds() - c1;
      encode_s += c1 - c0;
      bytes += static_cast<double>(jpeg.size());
      score(t);
    }
    run.fits_rate = bytes / frames <= budget_bytes * 1.05;
  } else {
    robot::video::AvVideoEncoderOptions options;
    options.codec = codec;
    options.width = base.width;
    options.height = base.height;
    options.fps = kComparisonFps;
    options.bit_rate_bps = static_cast<std::int64_t>(camera_bps);
    options.key_frame_interval = kKeyFrameInterval;
    options.threads = 1;  // ms on one core
    auto encoder = robot::video::AvVideoEncoder::open(options, &error);
    if (!encoder) throw std::runtime_error("codec: " + error);
    auto decoder = xr::video::AvVideoDecoder::open(codec, 1, &error);
    if (!decoder) throw std::runtime_error("codec: " + error);
    run.backend = encoder->backend();
    robot::video::EncodedVideoFrame packet;
    for (int t = 0; t < frames; ++t) {
      sequenceImage(base, t, image);
      const double c0 = threadCpuSeconds();
      const bool encoded = encoder->encode(image, false, packet, &error);
      const double c1 = threadCpuSeconds();
      encode_s += c1 - c0;
      if (!encoded) {
        ++late;  // held back: a frame of latency
        continue;
      }
      const auto result = decoder->decode(packet.bytes, packet.key_frame, decoded, &error);
      decode_s += threadCpuSeconds() - c1;
      bytes += static_cast<double>(packet.bytes.size());
      if (result != xr::video::AvDecodeResult::kFrame) {
        ++late;
        continue;
      }
      score(t);
    }
  }
  run.bytes_per_stereo_frame = 2.0 * bytes / frames;
  run.encode_ms = 1e3 * encode_s / frames;
  run.decode_ms = 1e3 * decode_s / frames;
  run.latency_frames = static_cast<double>(late) / frames;
  run.ssim = measured ? ssim / measured : 0.0;
  run.psnr_db = measured ? psnr / measured : 0.0;
  return run;
}

}  // namespace

nlohmann::json codecComparison(const BenchContext& ctx, const std::uint8_t* rgb, int width, int height) {
  struct Size {
    const char* name;
    bool half;
  };
  const std::vector<Size> sizes = ctx.quick ? std::vector<Size>{{"2x1080p", true}}
                                            : std::vector<Size>{{"2x1080p", true}, {"2x4K", false}};
  const std::vector<double> rates = ctx.quick ? std::vector<double>{20, 50} : std::vector<double>{10, 20, 50, 100};
  const int frames = ctx.quick ? 6 : 30;
  Table table({"stereo input", "codec", "Mbit/s", "bytes/stereo frame", "SSIM (Y)", "PSNR Y dB", "encode ms",
               "decode ms", "latency frames", "CPU ms/stereo frame", "encoder"});
  nlohmann::json rows = nlohmann::json::array(), goal = nlohmann::json::object();
  for (const Size& size : sizes) {
    const int w = size.half ? width / 2 : width, h = size.half ? height / 2 : height;
    const Yuv420Image base = size.half ? planesOf(halved(rgb, width, height), w, h)
                                       : planesOf(std::vector<std::uint8_t>(rgb, rgb + std::size_t(width) * height * 3), w, h);
    double best_at_20 = -1, mjpeg_at_50 = -1;
    std::string best_codec;
    for (link::VideoCodec codec : {link::VideoCodec::kMjpeg, link::VideoCodec::kH264, link::VideoCodec::kHevc}) {
      for (double rate : rates) {
        ctx.out << "codec: " << size.name << " " << link::videoCodecName(codec) << " at " << rate << " Mbit/s…\n"
                << std::flush;
        const CodecRun run = runCodecAtRate(codec, rate, base, frames);
        table.addRow({size.name, run.codec, formatNumber(rate),
                      formatNumber(run.bytes_per_stereo_frame) + (run.fits_rate ? "" : " (over)"),
                      formatNumber(run.ssim, 4), formatNumber(run.psnr_db, 3), formatNumber(run.encode_ms),
                      formatNumber(run.decode_ms), formatNumber(run.latency_frames),
                      formatNumber(2.0 * (run.encode_ms + run.decode_ms)), run.backend});
        rows.push_back({{"size", size.name}, {"codec", run.codec}, {"rate_mbit", rate},
                        {"bytes_per_stereo_frame", run.bytes_per_stereo_frame}, {"ssim", run.ssim},
                        {"psnr_db", run.psnr_db}, {"encode_ms", run.encode_ms}, {"decode_ms", run.decode_ms},
                        {"latency_frames", run.latency_frames}, {"backend", run.backend},
                        {"fits_rate", run.fits_rate}, {"mjpeg_quality", run.mjpeg_quality}});
        if (codec == link::VideoCodec::kMjpeg && rate == 50) mjpeg_at_50 = run.ssim;
        if (codec != link::VideoCodec::kMjpeg && rate == 20 && run.ssim > best_at_20) {
          best_at_20 = run.ssim;
          best_codec = run.codec;
        }
      }
    }
    goal[size.name] = {{"best_codec_at_20_mbit", best_codec}, {"ssim_at_20_mbit", best_at_20},
                       {"mjpeg_ssim_at_50_mbit", mjpeg_at_50}, {"met", best_at_20 >= mjpeg_at_50}};
  }
  ctx.out << "\nCodecs at the link's rates (" << frames << " images at " << kComparisonFps
          << " Hz panning " << kPanPxPerImage
          << " px an image with fresh sensor noise; one camera at half the rate, bytes doubled for the pair; "
             "SSIM and PSNR of the decoded Y against its source, every third image; encode and decode on one "
             "core (one thread), ms per image; MJPEG at the highest quality whose first image fits the rate):\n";
  table.print(ctx.out);
  for (const auto& [name, g] : goal.items())
    ctx.out << name << ": at 20 Mbit/s " << g["best_codec_at_20_mbit"].get<std::string>() << " reaches SSIM "
            << formatNumber(g["ssim_at_20_mbit"].get<double>(), 4) << ", MJPEG at 50 Mbit/s "
            << formatNumber(g["mjpeg_ssim_at_50_mbit"].get<double>(), 4) << ": goal "
            << (g["met"].get<bool>() ? "met" : "not met") << "\n";
  return {{"codecs", rows}, {"codec_goal", goal}};
}

}  // namespace telesphere::bench
