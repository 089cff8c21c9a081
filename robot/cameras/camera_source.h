// SPDX-License-Identifier: MIT
/// @brief The seam between a camera and the video path (DESIGN.md §4): a CameraSource delivers
///        CameraFrames, each stamped at capture in the host clock (robot::Clock, steady ns, the
///        same clock the joint-state buffer and the link use), with its sequence number, exposure
///        and pixel format. Implementations: AravisCamera (GenICam hardware, robot/cameras/aravis_camera.h)
///        and SyntheticCamera (a rendered scene, robot/cameras/synthetic_camera.h).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::robot::cameras {

/// Pixel layouts a camera may deliver. Bayer names give the colours of the top-left 2×2 cell.
enum class PixelFormat { kMono8, kRgb8, kBayerRG8, kBayerGR8, kBayerGB8, kBayerBG8 };

/// Bytes per pixel of `format` (all formats here are 8 bits per sample).
constexpr int bytesPerPixel(PixelFormat format) { return format == PixelFormat::kRgb8 ? 3 : 1; }

/// "Mono8", "RGB8", "BayerRG8", … (the GenICam PixelFormat names).
const char* pixelFormatName(PixelFormat format);

/// One image as the camera delivered it. Pixels are shared, never copied between stages.
struct CameraFrame {
  std::int64_t capture_ns = 0;  ///< host clock (steady ns): middle of the exposure where known
  std::uint64_t sequence = 0;   ///< the camera's own frame counter (gaps mean lost frames)
  std::uint32_t exposure_us = 0;
  PixelFormat format = PixelFormat::kRgb8;
  int width = 0;
  int height = 0;
  int stride_bytes = 0;  ///< bytes from one row to the next
  std::shared_ptr<const std::vector<std::uint8_t>> pixels;
  bool timestamp_from_hardware = false;  ///< capture_ns mapped from the camera's clock
};

/// Counters a camera keeps from start() on; never reset while it runs.
struct CameraStats {
  std::uint64_t frames = 0;      ///< delivered by nextFrame()
  std::uint64_t incomplete = 0;  ///< buffers dropped because they were incomplete or corrupt
  std::uint64_t lost = 0;        ///< gaps in the camera's sequence numbers
  std::uint64_t reconnects = 0;  ///< times the camera disappeared and was opened again
  std::string last_error;        ///< empty while all is well
};

class CameraSource {
 public:
  virtual ~CameraSource() = default;

  /// A name for logs and errors ("Fake_1", "synthetic-left", a serial number).
  virtual std::string name() const = 0;

  /// Opens and starts acquisition; false with *error set when that is impossible.
  virtual bool start(std::string* error) = 0;

  /// Stops acquisition; nextFrame() then returns nullopt at once. Idempotent.
  virtual void stop() = 0;

  /// The next frame, waiting up to `timeout`; nullopt on timeout or when stopped.
  virtual std::optional<CameraFrame> nextFrame(std::chrono::milliseconds timeout) = 0;

  virtual CameraStats stats() const = 0;
};

}  // namespace telesphere::robot::cameras
