// SPDX-License-Identifier: MIT
/// @brief The depth bench's moving scene (`telesphere-bench depth`, #35): an object approaching the
///        cameras, swept image by image, through the temporal filter (xr/depth/inverse_depth_filter.h)
///        and without; and the filter's knobs both ways (swim at rest against lag approaching).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/bench_topic.h"
#include "app/bench/depth_bench_stereo.h"
#include "robot/cameras/synthetic_scene.h"

namespace telesphere::bench::depth_bench {

/// An object approaching the cameras at 0.5 m/s from 1.5 m to 0.3 m, swept at 10 Hz (5 Hz quick):
/// each image's scene and its left camera's sweep (the filters run over these afterwards).
struct ApproachFrames {
  double rate_hz = 10.0, speed_m_s = 0.5, from_m = 1.5, to_m = 0.3;
  std::vector<robot::cameras::SyntheticScene> scenes;
  std::vector<xr::depth::SweepResult> sweeps;
};

/// The approach's images rendered and each swept by the left camera's sweep of `sweeps`.
ApproachFrames sweepApproach(const BenchContext& ctx, StereoSweeps& sweeps, const calib::SystemCalibration& rig, int depth_width,
                             int depth_height);

/// The approach with the default filter: the fixed sphere, the radius and grid of each image's
/// sweep and of the sweep before, and the grid unfiltered.
nlohmann::json runApproach(const BenchContext& ctx, const ApproachFrames& frames);

/// The temporal filter's knobs both ways: what the operator sees swim at rest (a still scene, a
/// fresh σ 8 sensor noise on every capture) against how far an approaching object is off.
nlohmann::json runFilterKnob(const BenchContext& ctx, StereoSweeps& sweeps, const calib::SystemCalibration& rig,
                             const ApproachFrames& approach, int depth_width, int depth_height);

}  // namespace telesphere::bench::depth_bench
