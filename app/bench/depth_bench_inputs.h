// SPDX-License-Identifier: MIT
/// @brief The depth bench's harder inputs (`telesphere-bench depth`, #35): the sweep on the pair as
///        the operator gets it (the robot's JPEG, sensor noise, a stereo calibration the cameras no
///        longer match) and with a second baseline from the arm's motion (earlier views).
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "app/bench/bench_topic.h"
#include "app/bench/depth_bench_stereo.h"

namespace telesphere::bench::depth_bench {

/// What happens to the pair between the sensors and the sweep: the robot's JPEG, sensor noise, a
/// stereo calibration the cameras no longer match. Applied at the capture size, before the
/// operator's box filter down to the sweep's size.
struct InputVariant {
  std::string name;
  int jpeg_quality = 0;      // 0: no JPEG
  double noise_grey = 0;     // σ of Gaussian noise per capture pixel, grey levels
  Eigen::Vector3d rig_error_deg{0, 0, 0};  // the right camera turned about its x, y, z axes
};

/// The capture-size grey pair as the operator would sweep it: noise, JPEG there and back (the
/// robot's encoder, the XR app's decoder), then box-filtered by `factor`.
StereoGrey degradeAndShrink(const StereoGrey& capture, int width, int height, int factor, const InputVariant& v,
                            std::uint32_t seed);

/// Harder inputs on the 0.5 m scene and the stripes: each variant's matched tiles, inverse-depth
/// error and the stereo proxies' moving eye errors.
nlohmann::json runHarderInputs(const BenchContext& ctx, StereoSweeps& sweeps, const calib::CameraCalibration& left_camera,
                               int depth_width, int depth_height);

/// A second baseline from the arm's motion (SphereSweep's earlier views): both cameras' images from
/// where the rig was before (translated, not turned), swept with the pair now. On the stripes, which
/// the pair alone cannot decide, and on the 0.5 m scene, which it can (what the views cost there).
nlohmann::json runMotionBaselines(const BenchContext& ctx, StereoSweeps& sweeps, const calib::SystemCalibration& rig, int width,
                                  int height);

}  // namespace telesphere::bench::depth_bench
