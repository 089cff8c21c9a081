// SPDX-License-Identifier: MIT
/// @brief StereoEncoder: caller thread + one worker, a condition-variable hand-off per pair.
#include "robot/video/stereo_encoder.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "robot/cameras/debayer.h"
#include "robot/cameras/debayer_yuv420.h"
#include "robot/cameras/reusable_buffers.h"

namespace telesphere::robot::video {
namespace stereo_encoder_detail {  // named: Impl's members use it (-Wsubobject-linkage)

/// What one side keeps between frames: its encoder, and for a camera that sends its raw Bayer
/// mosaic the planes (or, for 4:4:4 and 4:2:2, the RGB image) it is debayered into.
struct StereoEncoderSide {
  JpegEncoder jpeg;
  cameras::ReusableBuffers pool;  ///< JPEG buffers, reused once the link has sent them
  cameras::DebayerToYuv420 to_planes;
  cameras::Yuv420Image planes;
  std::vector<std::uint8_t> rgb;
};

bool encodeFrame(StereoEncoderSide& side, const clock::Clock& clock, const cameras::CameraFrame& frame,
                 const JpegSettings& settings, EncodedImage& out, std::string* error) {
  if (!frame.pixels || frame.width <= 0 || frame.height <= 0 ||
      frame.pixels->size() < static_cast<std::size_t>(frame.stride_bytes) * frame.height) {
    *error = "frame " + std::to_string(frame.sequence) + " has no or too few pixel bytes";
    return false;
  }
  const std::int64_t start_ns = clock.nowNs();
  auto buffer = side.pool.acquire();
  bool ok = false;
  const std::uint8_t* pixels = frame.pixels->data();
  if (frame.format == cameras::PixelFormat::kRgb8) {
    ok = side.jpeg.encodeRgb(pixels, frame.width, frame.height, frame.stride_bytes, settings, *buffer, error);
  } else if (frame.format == cameras::PixelFormat::kMono8) {
    ok = side.jpeg.encodeGray(pixels, frame.width, frame.height, frame.stride_bytes, settings, *buffer, error);
  } else if (settings.subsampling == ChromaSubsampling::k420 || settings.subsampling == ChromaSubsampling::kGray) {
    // A raw mosaic straight into the planes the encoder compresses (no RGB image, #34).
    ok = side.to_planes.convert(pixels, frame.width, frame.height, frame.stride_bytes, frame.format, side.planes,
                                error) &&
         side.jpeg.encodeYuv420(side.planes, settings, *buffer, error);
  } else {
    // 4:4:4 and 4:2:2 need chroma at full (or half) width: through an RGB image, slower.
    ok = cameras::debayerBilinear(pixels, frame.width, frame.height, frame.stride_bytes, frame.format, side.rgb,
                                  error) &&
         side.jpeg.encodeRgb(side.rgb.data(), frame.width, frame.height, frame.width * 3, settings, *buffer, error);
  }
  if (!ok) return false;
  out.encoded_ns = clock.nowNs();
  out.encode_ms = static_cast<double>(out.encoded_ns - start_ns) * 1e-6;
  out.jpeg = std::move(buffer);
  return true;
}

}  // namespace stereo_encoder_detail

using stereo_encoder_detail::encodeFrame;
using stereo_encoder_detail::StereoEncoderSide;

struct StereoEncoder::Impl {
  const clock::Clock& clock;
  JpegSettings settings;
  mutable std::mutex settings_mutex;

  StereoEncoderSide left, right;

  // Hand-off to the worker: one job at a time.
  std::mutex mutex;
  std::condition_variable cv;
  const cameras::CameraFrame* job = nullptr;
  JpegSettings job_settings;
  EncodedImage* job_out = nullptr;
  bool job_done = false, job_ok = false, quit = false;
  std::string job_error;
  std::thread worker;

  Impl(const clock::Clock& c, const JpegSettings& s) : clock(c), settings(s) {
    worker = std::thread([this] { run(); });
  }

  void run() {
    std::unique_lock lock(mutex);
    for (;;) {
      cv.wait(lock, [this] { return quit || (job && !job_done); });
      if (quit) return;
      const cameras::CameraFrame& frame = *job;
      const JpegSettings s = job_settings;
      EncodedImage* out = job_out;
      lock.unlock();
      std::string error;
      const bool ok = encodeFrame(right, clock, frame, s, *out, &error);
      lock.lock();
      job_ok = ok;
      job_error = std::move(error);
      job_done = true;
      cv.notify_all();
    }
  }
};

StereoEncoder::StereoEncoder(const clock::Clock& clock, const JpegSettings& settings)
    : impl_(std::make_unique<Impl>(clock, settings)) {}

StereoEncoder::~StereoEncoder() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->quit = true;
  }
  impl_->cv.notify_all();
  impl_->worker.join();
}

void StereoEncoder::setSettings(const JpegSettings& settings) {
  std::lock_guard lock(impl_->settings_mutex);
  impl_->settings = settings;
}

JpegSettings StereoEncoder::settings() const {
  std::lock_guard lock(impl_->settings_mutex);
  return impl_->settings;
}

bool StereoEncoder::encode(const cameras::CameraFrame& left, const cameras::CameraFrame& right, EncodedPair& out,
                           std::string* error) {
  return encode(left, right, settings(), out, error);
}

bool StereoEncoder::encode(const cameras::CameraFrame& left, const cameras::CameraFrame& right,
                           const JpegSettings& s, EncodedPair& out, std::string* error) {
  out.settings = s;
  {
    std::lock_guard lock(impl_->mutex);
    impl_->job = &right;
    impl_->job_settings = s;
    impl_->job_out = &out.right;
    impl_->job_done = false;
  }
  impl_->cv.notify_all();
  std::string left_error;
  const bool left_ok =
      encodeFrame(impl_->left, impl_->clock, left, s, out.left, &left_error);
  std::unique_lock lock(impl_->mutex);
  impl_->cv.wait(lock, [this] { return impl_->job_done; });
  impl_->job = nullptr;
  if (!left_ok) {
    *error = "left: " + left_error;
    return false;
  }
  if (!impl_->job_ok) {
    *error = "right: " + impl_->job_error;
    return false;
  }
  return true;
}

}  // namespace telesphere::robot::video
