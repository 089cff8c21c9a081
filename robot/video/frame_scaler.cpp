// SPDX-License-Identifier: MIT
/// @brief scaleFrame over cv::resize(INTER_AREA).
#include "robot/video/frame_scaler.h"

#include <opencv2/imgproc.hpp>

#include "robot/cameras/debayer.h"

#include <algorithm>
#include <cmath>

namespace telesphere::robot::video {

std::pair<int, int> scaledSize(int width, int height, double scale) {
  const auto side = [&](int full) {
    if (scale >= 1.0) return full;
    const int even = 2 * static_cast<int>(std::lround(full * scale / 2));
    return std::min(full, std::max(16, even));
  };
  return {side(width), side(height)};
}

cameras::CameraFrame scaleFrame(const cameras::CameraFrame& frame, double scale) {
  const auto [w, h] = scaledSize(frame.width, frame.height, scale);
  if ((w == frame.width && h == frame.height) || !frame.pixels) return frame;
  if (cameras::isBayer(frame.format)) {
    // A mosaic cannot be resampled as it is: debayered first, then scaled as an RGB image.
    cameras::CameraFrame rgb = frame;
    auto pixels = std::make_shared<std::vector<std::uint8_t>>();
    if (!cameras::debayerBilinear(frame.pixels->data(), frame.width, frame.height, frame.stride_bytes, frame.format,
                                  *pixels, nullptr))
      return frame;  // smaller than one 2 × 2 cell: sent as it is (the encoder says why it cannot)
    rgb.format = cameras::PixelFormat::kRgb8;
    rgb.stride_bytes = frame.width * 3;
    rgb.pixels = std::move(pixels);
    return scaleFrame(rgb, scale);
  }
  const int channels = frame.format == cameras::PixelFormat::kMono8 ? 1 : 3;
  const int type = channels == 1 ? CV_8UC1 : CV_8UC3;
  const cv::Mat source(frame.height, frame.width, type, const_cast<std::uint8_t*>(frame.pixels->data()),
                       static_cast<std::size_t>(frame.stride_bytes));
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(w) * h * channels);
  cv::Mat target(h, w, type, pixels->data());
  cv::resize(source, target, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  cameras::CameraFrame out = frame;
  out.width = w;
  out.height = h;
  out.stride_bytes = w * channels;
  out.pixels = std::move(pixels);
  return out;
}

}  // namespace telesphere::robot::video
