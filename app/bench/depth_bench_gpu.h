// SPDX-License-Identifier: MIT
/// @brief The depth bench's GPU sweep (`telesphere-bench depth`, #35): the pair's cost volume on the
///        GPU (xr/depth/gpu_sweep_costs.h) against the CPU's, at the default 4° tiles and at 2°
///        (four times the tiles), on the bench's scenes: time a pair, the calling thread's CPU time,
///        and how far the grids differ.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/bench_topic.h"
#include "app/bench/depth_bench_scenes.h"
#include "robot/cameras/synthetic_scene.h"

namespace telesphere::bench::depth_bench {

/// Null (and a line saying why) where no GL 4.5 context with compute shaders can be made.
nlohmann::json runGpuSweep(const BenchContext& ctx, const calib::SystemCalibration& rig, int width, int height,
                           const std::vector<robot::cameras::SyntheticScene>& scenes, const std::vector<StereoGrey>& pairs);

}  // namespace telesphere::bench::depth_bench
