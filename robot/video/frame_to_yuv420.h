// SPDX-License-Identifier: MIT
/// @brief Any camera image as the YUV 4:2:0 planes an H.264/HEVC encoder takes (#34), in JPEG's
///        colour space (JFIF: BT.601, full range) like the JPEG path: a Bayer mosaic debayered
///        straight into planes (DebayerToYuv420), RGB through TurboJPEG's own conversion (the
///        planes a JPEG of it would hold), grey as Y with neutral chroma. The planes keep their
///        memory between images of one size.
#pragma once

#include <memory>
#include <string>

#include "robot/cameras/camera_source.h"
#include "robot/cameras/yuv420_image.h"

namespace telesphere::robot::video {

class FrameToYuv420 {
 public:
  FrameToYuv420();
  ~FrameToYuv420();
  FrameToYuv420(const FrameToYuv420&) = delete;
  FrameToYuv420& operator=(const FrameToYuv420&) = delete;

  /// Fills `out` from `frame` (any PixelFormat; width, height ≥ 2); false with the reason on a
  /// frame that does not hold what it says.
  bool convert(const cameras::CameraFrame& frame, cameras::Yuv420Image& out, std::string* error);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::robot::video
