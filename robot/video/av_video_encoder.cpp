// SPDX-License-Identifier: MIT
/// @brief AvVideoEncoder over libavcodec's send/receive API: the encoder's options per backend,
///        the planes copied into one writable frame kept for the encoder's life.
#include "robot/video/av_video_encoder.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

#include <algorithm>
#include <cstring>
#include <mutex>

namespace telesphere::robot::video {
namespace {

/// libavcodec and its encoders log to stderr; only their errors belong in our logs.
void quietLibav() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_ERROR); });
}

std::string avError(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

/// The libavcodec encoder names of a codec: the GPU's first when asked for.
std::vector<std::string> encoderNames(link::VideoCodec codec, bool prefer_gpu) {
  const bool hevc = codec == link::VideoCodec::kHevc;
  std::vector<std::string> names;
  if (prefer_gpu) names.emplace_back(hevc ? "hevc_nvenc" : "h264_nvenc");
  names.emplace_back(hevc ? "libx265" : "libx264");
  return names;
}

/// Latency first: no B-frames, no lookahead, every image out at once, forced key frames as IDR.
void setLowLatencyOptions(AVCodecContext* ctx, const std::string& name, int key_frame_interval) {
  void* priv = ctx->priv_data;
  if (name == "libx264") {
    av_opt_set(priv, "preset", "ultrafast", 0);
    av_opt_set(priv, "tune", "zerolatency", 0);  // also sliced threads, no lookahead
    av_opt_set_int(priv, "forced-idr", 1, 0);
  } else if (name == "libx265") {
    av_opt_set(priv, "preset", "ultrafast", 0);
    av_opt_set(priv, "tune", "zerolatency", 0);
    av_opt_set_int(priv, "forced-idr", 1, 0);
    // One frame thread (more hold images back: latency); wavefront threads within the image.
    const std::string params =
        "keyint=" + std::to_string(key_frame_interval) + ":bframes=0:frame-threads=1:log-level=error";
    av_opt_set(priv, "x265-params", params.c_str(), 0);
  } else {  // NVENC
    av_opt_set(priv, "preset", "p1", 0);
    av_opt_set(priv, "tune", "ull", 0);
    av_opt_set_int(priv, "zerolatency", 1, 0);
    av_opt_set_int(priv, "delay", 0, 0);
    av_opt_set_int(priv, "forced-idr", 1, 0);
    av_opt_set(priv, "rc", "cbr", 0);
  }
}

}  // namespace

struct AvVideoEncoder::Impl {
  AvVideoEncoderOptions options;
  std::string backend, gpu_fallback_reason;
  AVCodecContext* ctx = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  std::int64_t next_index = 0, held_back = 0;

  ~Impl() {
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&ctx);
  }

  void applyRate(std::int64_t bit_rate_bps) {
    ctx->bit_rate = bit_rate_bps;
    ctx->rc_max_rate = bit_rate_bps;
    // About one image's worth of buffer: the rate holds image by image (no burst to queue).
    ctx->rc_buffer_size = static_cast<int>(std::min<std::int64_t>(bit_rate_bps / std::max(options.fps, 1) * 2, 1 << 30));
  }

  /// Opens `name`; false with the reason.
  bool openCodec(const std::string& name, std::string* error) {
    const AVCodec* codec = avcodec_find_encoder_by_name(name.c_str());
    if (!codec) {
      *error = name + ": not in this libavcodec";
      return false;
    }
    avcodec_free_context(&ctx);
    ctx = avcodec_alloc_context3(codec);
    if (!ctx) {
      *error = name + ": out of memory";
      return false;
    }
    ctx->width = options.width;
    ctx->height = options.height;
    ctx->pix_fmt = AV_PIX_FMT_YUV420P;
    ctx->color_range = AVCOL_RANGE_JPEG;  // the camera path's planes are JFIF: full range, BT.601
    ctx->colorspace = AVCOL_SPC_BT470BG;
    ctx->time_base = AVRational{1, options.fps};
    ctx->framerate = AVRational{options.fps, 1};
    ctx->gop_size = options.key_frame_interval;
    ctx->max_b_frames = 0;
    ctx->thread_count = options.threads;
    ctx->thread_type = FF_THREAD_SLICE;
    applyRate(options.bit_rate_bps);
    setLowLatencyOptions(ctx, name, options.key_frame_interval);
    const int rc = avcodec_open2(ctx, codec, nullptr);
    if (rc < 0) {
      *error = name + ": " + avError(rc);
      avcodec_free_context(&ctx);
      return false;
    }
    backend = name;
    return true;
  }
};

AvVideoEncoder::AvVideoEncoder(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
AvVideoEncoder::~AvVideoEncoder() = default;

std::unique_ptr<AvVideoEncoder> AvVideoEncoder::open(const AvVideoEncoderOptions& options, std::string* error) {
  if (options.codec == link::VideoCodec::kMjpeg) {
    *error = "AvVideoEncoder encodes H.264 and HEVC; MJPEG is JpegEncoder's";
    return nullptr;
  }
  if (options.width < 16 || options.height < 16 || options.width % 2 || options.height % 2) {
    *error = "AvVideoEncoder: " + std::to_string(options.width) + "x" + std::to_string(options.height) +
             " is not an even size of at least 16x16";
    return nullptr;
  }
  if (options.fps < 1 || options.bit_rate_bps < 10'000 || options.key_frame_interval < 1) {
    *error = "AvVideoEncoder: rate " + std::to_string(options.fps) + " Hz, " + std::to_string(options.bit_rate_bps) +
             " bit/s and a key frame every " + std::to_string(options.key_frame_interval) +
             " images: each must be positive (at least 10 kbit/s)";
    return nullptr;
  }
  quietLibav();
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  std::string reasons;
  for (const std::string& name : encoderNames(options.codec, options.prefer_gpu)) {
    std::string why;
    if (impl->openCodec(name, &why)) break;
    reasons.append(reasons.empty() ? "" : "; ").append(why);
  }
  if (impl->backend.empty()) {
    *error = "AvVideoEncoder: no " + std::string(link::videoCodecName(options.codec)) + " encoder opened (" + reasons + ")";
    return nullptr;
  }
  if (options.prefer_gpu) impl->gpu_fallback_reason = reasons;  // empty when the GPU's opened
  impl->frame = av_frame_alloc();
  impl->packet = av_packet_alloc();
  if (!impl->frame || !impl->packet) {
    *error = "AvVideoEncoder: out of memory";
    return nullptr;
  }
  impl->frame->format = AV_PIX_FMT_YUV420P;
  impl->frame->width = options.width;
  impl->frame->height = options.height;
  impl->frame->color_range = AVCOL_RANGE_JPEG;
  if (const int rc = av_frame_get_buffer(impl->frame, 0); rc < 0) {
    *error = "AvVideoEncoder: " + avError(rc);
    return nullptr;
  }
  return std::unique_ptr<AvVideoEncoder>(new AvVideoEncoder(std::move(impl)));
}

bool AvVideoEncoder::encode(const cameras::Yuv420Image& image, bool key_frame, EncodedVideoFrame& out,
                            std::string* error) {
  Impl& m = *impl_;
  if (image.width != m.options.width || image.height != m.options.height) {
    *error = "AvVideoEncoder: a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
             " image for an encoder opened at " + std::to_string(m.options.width) + "x" + std::to_string(m.options.height);
    return false;
  }
  if (const int rc = av_frame_make_writable(m.frame); rc < 0) {
    *error = "AvVideoEncoder: " + avError(rc);
    return false;
  }
  const auto copyPlane = [](const std::vector<std::uint8_t>& from, int width, int height, std::uint8_t* to, int linesize) {
    for (int y = 0; y < height; ++y)
      std::memcpy(to + static_cast<std::ptrdiff_t>(y) * linesize, from.data() + static_cast<std::size_t>(y) * width,
                  static_cast<std::size_t>(width));
  };
  copyPlane(image.y, image.width, image.height, m.frame->data[0], m.frame->linesize[0]);
  copyPlane(image.u, image.chromaWidth(), image.chromaHeight(), m.frame->data[1], m.frame->linesize[1]);
  copyPlane(image.v, image.chromaWidth(), image.chromaHeight(), m.frame->data[2], m.frame->linesize[2]);
  m.frame->pts = m.next_index++;
  m.frame->pict_type = key_frame ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
  if (const int rc = avcodec_send_frame(m.ctx, m.frame); rc < 0) {
    *error = "AvVideoEncoder (" + m.backend + "): " + avError(rc);
    return false;
  }
  const int rc = avcodec_receive_packet(m.ctx, m.packet);
  if (rc == AVERROR(EAGAIN)) {
    ++m.held_back;
    *error = "AvVideoEncoder (" + m.backend + "): held the image back (not zero latency)";
    return false;
  }
  if (rc < 0) {
    *error = "AvVideoEncoder (" + m.backend + "): " + avError(rc);
    return false;
  }
  out.bytes.assign(m.packet->data, m.packet->data + m.packet->size);
  out.key_frame = (m.packet->flags & AV_PKT_FLAG_KEY) != 0;
  out.index = m.packet->pts;
  av_packet_unref(m.packet);
  return true;
}

void AvVideoEncoder::setBitRate(std::int64_t bit_rate_bps) {
  // libx264 and NVENC pick up a changed rate at the next image (their wrappers reconfigure);
  // libx265's does not (see the header).
  impl_->options.bit_rate_bps = bit_rate_bps;
  impl_->applyRate(bit_rate_bps);
}

bool AvVideoEncoder::changesRateInPlace() const { return impl_->backend != "libx265"; }
std::string AvVideoEncoder::backend() const { return impl_->backend; }
std::string AvVideoEncoder::gpuFallbackReason() const { return impl_->gpu_fallback_reason; }
std::int64_t AvVideoEncoder::heldBack() const { return impl_->held_back; }

}  // namespace telesphere::robot::video
