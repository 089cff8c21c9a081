// SPDX-License-Identifier: MIT
/// @brief AvVideoDecoder over libavcodec's send/receive API.
#include "xr/video/av_video_decoder.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/pixdesc.h>
}

#include <cstring>

namespace telesphere::xr::video {
namespace {

std::string avError(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

}  // namespace

struct AvVideoDecoder::Impl {
  AVCodecContext* ctx = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  bool waiting_for_key = false;

  ~Impl() {
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&ctx);
  }
};

AvVideoDecoder::AvVideoDecoder(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
AvVideoDecoder::~AvVideoDecoder() = default;

std::unique_ptr<AvVideoDecoder> AvVideoDecoder::open(link::VideoCodec codec, int threads, std::string* error) {
  if (codec == link::VideoCodec::kMjpeg) {
    *error = "AvVideoDecoder decodes H.264 and HEVC; MJPEG is JpegDecoder's";
    return nullptr;
  }
  const AVCodec* decoder = avcodec_find_decoder(codec == link::VideoCodec::kHevc ? AV_CODEC_ID_HEVC : AV_CODEC_ID_H264);
  if (!decoder) {
    *error = std::string("AvVideoDecoder: this libavcodec has no ") + link::videoCodecName(codec) + " decoder";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>();
  impl->ctx = avcodec_alloc_context3(decoder);
  impl->frame = av_frame_alloc();
  impl->packet = av_packet_alloc();
  if (!impl->ctx || !impl->frame || !impl->packet) {
    *error = "AvVideoDecoder: out of memory";
    return nullptr;
  }
  impl->ctx->flags |= AV_CODEC_FLAG_LOW_DELAY;  // no reordering delay: an image out per image in
  impl->ctx->thread_count = threads;
  impl->ctx->thread_type = FF_THREAD_SLICE;  // frame threads would hold images back
  if (const int rc = avcodec_open2(impl->ctx, decoder, nullptr); rc < 0) {
    *error = std::string("AvVideoDecoder: ") + avError(rc);
    return nullptr;
  }
  return std::unique_ptr<AvVideoDecoder>(new AvVideoDecoder(std::move(impl)));
}

void AvVideoDecoder::markLost() { impl_->waiting_for_key = true; }
bool AvVideoDecoder::waitingForKeyFrame() const { return impl_->waiting_for_key; }

AvDecodeResult AvVideoDecoder::decode(std::span<const std::uint8_t> bytes, bool key_frame, render::YuvPlanes& out,
                                      std::string* error) {
  Impl& m = *impl_;
  if (m.waiting_for_key && !key_frame) return AvDecodeResult::kWaitingForKeyFrame;
  m.packet->data = const_cast<std::uint8_t*>(bytes.data());  // not refcounted: libavcodec copies it
  m.packet->size = static_cast<int>(bytes.size());
  int rc = avcodec_send_packet(m.ctx, m.packet);
  m.packet->data = nullptr;
  m.packet->size = 0;
  if (rc < 0) {
    *error = std::string("AvVideoDecoder: ") + avError(rc);
    m.waiting_for_key = true;
    return AvDecodeResult::kError;
  }
  rc = avcodec_receive_frame(m.ctx, m.frame);
  if (rc == AVERROR(EAGAIN)) return AvDecodeResult::kNoFrame;
  if (rc < 0) {
    *error = std::string("AvVideoDecoder: ") + avError(rc);
    m.waiting_for_key = true;
    return AvDecodeResult::kError;
  }
  m.waiting_for_key = false;
  const AVFrame& f = *m.frame;
  if (f.format != AV_PIX_FMT_YUV420P && f.format != AV_PIX_FMT_YUVJ420P) {
    const char* name = av_get_pix_fmt_name(static_cast<AVPixelFormat>(f.format));
    *error = std::string("AvVideoDecoder: decoded ") + (name ? name : "an unknown format") + ", not YUV 4:2:0";
    av_frame_unref(m.frame);
    return AvDecodeResult::kError;
  }
  out.slot.reset();
  out.width = f.width;
  out.height = f.height;
  out.chroma_width = (f.width + 1) / 2;
  out.chroma_height = (f.height + 1) / 2;
  out.subsampling = link::ChromaSubsampling::k420;
  const auto copyPlane = [](const std::uint8_t* from, int linesize, int width, int height, std::vector<std::uint8_t>& to) {
    to.resize(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
      std::memcpy(to.data() + static_cast<std::size_t>(y) * width, from + static_cast<std::ptrdiff_t>(y) * linesize,
                  static_cast<std::size_t>(width));
  };
  copyPlane(f.data[0], f.linesize[0], out.width, out.height, out.y);
  copyPlane(f.data[1], f.linesize[1], out.chroma_width, out.chroma_height, out.u);
  copyPlane(f.data[2], f.linesize[2], out.chroma_width, out.chroma_height, out.v);
  av_frame_unref(m.frame);
  return AvDecodeResult::kFrame;
}

}  // namespace telesphere::xr::video
