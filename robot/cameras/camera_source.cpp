// SPDX-License-Identifier: MIT
#include "robot/cameras/camera_source.h"

namespace telesphere::robot::cameras {

const char* pixelFormatName(PixelFormat format) {
  switch (format) {
    case PixelFormat::kMono8: return "Mono8";
    case PixelFormat::kRgb8: return "RGB8";
    case PixelFormat::kBayerRG8: return "BayerRG8";
    case PixelFormat::kBayerGR8: return "BayerGR8";
    case PixelFormat::kBayerGB8: return "BayerGB8";
    case PixelFormat::kBayerBG8: return "BayerBG8";
  }
  return "unknown";
}

}  // namespace telesphere::robot::cameras
