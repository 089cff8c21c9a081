// SPDX-License-Identifier: MIT
/// @brief A camera frame at a smaller scale, for a link that cannot carry the full one (DESIGN.md
///        §9): OpenCV's area resampling (every source pixel weighs in, no aliasing), sizes rounded
///        to even numbers (4:2:0 chroma), never below 16 px a side. The operator side rescales the
///        calibration to whatever size arrives (calib/camera_resolution.h).
#pragma once

#include "robot/cameras/camera_source.h"

namespace telesphere::robot::video {

/// The size `scale` (0 < scale ≤ 1, per axis) gives a width × height image.
std::pair<int, int> scaledSize(int width, int height, double scale);

/// `frame` (RGB8 or Mono8) resampled to scaledSize; the frame itself when scale is 1 (no copy).
/// A Bayer mosaic is debayered (bilinear) and returned as a scaled RGB8 frame. Stamps, sequence
/// and exposure are kept.
cameras::CameraFrame scaleFrame(const cameras::CameraFrame& frame, double scale);

}  // namespace telesphere::robot::video
