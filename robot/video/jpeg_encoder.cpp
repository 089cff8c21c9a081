// SPDX-License-Identifier: MIT
/// @brief JpegEncoder over tjCompress2.
#include "robot/video/jpeg_encoder.h"

#include <turbojpeg.h>

#include <stdexcept>

namespace telesphere::robot::video {
namespace {

int tjSubsampling(ChromaSubsampling s) {
  switch (s) {
    case ChromaSubsampling::k420: return TJSAMP_420;
    case ChromaSubsampling::k422: return TJSAMP_422;
    case ChromaSubsampling::k444: return TJSAMP_444;
    case ChromaSubsampling::kGray: return TJSAMP_GRAY;
  }
  return TJSAMP_420;
}

}  // namespace

JpegEncoder::JpegEncoder() : handle_(tjInitCompress()) {
  if (!handle_) throw std::runtime_error(std::string("tjInitCompress: ") + tjGetErrorStr2(nullptr));
}

JpegEncoder::~JpegEncoder() { tjDestroy(handle_); }

bool JpegEncoder::encodeRgb(const std::uint8_t* rgb, int width, int height, int stride,
                            const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                            std::string* error) {
  return encode(rgb, width, height, stride, 3, settings, out_jpeg, error);
}

bool JpegEncoder::encodeGray(const std::uint8_t* gray, int width, int height, int stride,
                             const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                             std::string* error) {
  return encode(gray, width, height, stride, 1, settings, out_jpeg, error);
}

bool JpegEncoder::encode(const std::uint8_t* pixels, int width, int height, int stride,
                         int channels, const JpegSettings& settings,
                         std::vector<std::uint8_t>& out_jpeg, std::string* error) {
  if (width <= 0 || height <= 0 || width > 65500 || height > 65500 ||
      stride < channels * width) {
    *error = "bad image size " + std::to_string(width) + "x" + std::to_string(height) +
             " with stride " + std::to_string(stride);
    return false;
  }
  if (settings.quality < 1 || settings.quality > 100) {
    *error = "JPEG quality " + std::to_string(settings.quality) + " is outside 1..100";
    return false;
  }
  const int subsampling = channels == 1 ? TJSAMP_GRAY : tjSubsampling(settings.subsampling);
  // Encode straight into our buffer (sized for the worst case) so nothing is copied afterwards.
  const unsigned long capacity = tjBufSize(width, height, subsampling);
  out_jpeg.resize(capacity);
  unsigned char* dst = out_jpeg.data();
  unsigned long size = capacity;
  const int flags = TJFLAG_NOREALLOC | TJFLAG_FASTDCT;
  if (tjCompress2(handle_, pixels, width, stride, height,
                  channels == 1 ? TJPF_GRAY : TJPF_RGB, &dst, &size, subsampling,
                  settings.quality, flags) != 0) {
    *error = std::string("tjCompress2: ") + tjGetErrorStr2(handle_);
    return false;
  }
  out_jpeg.resize(size);
  return true;
}

}  // namespace telesphere::robot::video
