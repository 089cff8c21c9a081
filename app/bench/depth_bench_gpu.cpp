// SPDX-License-Identifier: MIT
/// @brief The depth bench's GPU sweep against the CPU's, both cameras a pair.
#include "app/bench/depth_bench_gpu.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "app/bench/bench_table.h"
#include "app/bench/cpu_time.h"
#include "shaders/egl_context.h"
#include "xr/depth/gpu_sweep_costs.h"

namespace telesphere::bench::depth_bench {

nlohmann::json runGpuSweep(const BenchContext& ctx, const calib::SystemCalibration& rig, int width, int height,
                           const std::vector<robot::cameras::SyntheticScene>& scenes, const std::vector<StereoGrey>& pairs) {
  auto& out = ctx.out;
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  if (!context) {
    out << "\nThe sweep's pair costs on the GPU: not measured, no GL 4.5 context (" << error << ")\n";
    return nullptr;
  }
  const std::string renderer = context->renderer();
  const int repeats = ctx.quick ? 2 : 5;
  Table table({"tiles", "where the pair's costs are computed", "ms/pair (wall)", "CPU ms/pair (calling thread)",
               "tiles matched (both cameras)", "grid differs from the CPU's, max 1/m", "tiles > 0.01 1/m apart"});
  nlohmann::json rows = nlohmann::json::array();
  for (const double tile_deg : {4.0, 2.0}) {
    xr::depth::SphereSweepOptions options;
    options.tile_deg = tile_deg;
    const xr::depth::SphereSweep left(rig.cameras[0].camera, width, height, rig.cameras[1].camera, width, height,
                                      rig.T_cam_l_cam_r->inverse(), options);
    const xr::depth::SphereSweep right(rig.cameras[1].camera, width, height, rig.cameras[0].camera, width, height,
                                       *rig.T_cam_l_cam_r, options);
    const auto gpu_left = xr::depth::GpuSweepCosts::create(left, &error);
    const auto gpu_right = gpu_left ? xr::depth::GpuSweepCosts::create(right, &error) : nullptr;
    if (!gpu_right) {  // the rows measured so far stay
      out << "\nThe sweep's pair costs on the GPU at " << formatNumber(tile_deg) << " deg tiles: not measured (" << error << ")\n";
      break;
    }
    struct Timing {
      double wall_ms = 0, cpu_ms = 0;
      int matched = 0;
      std::vector<xr::render::InverseDepthGrid> grids;
    };
    Timing cpu, on_gpu;
    std::string gpu_error;
    for (const bool use_gpu : {false, true}) {
      Timing& t = use_gpu ? on_gpu : cpu;
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        const xr::depth::GreyImage l{pairs[i].left.data(), width, height, width}, r{pairs[i].right.data(), width, height, width};
        const auto sweepPair = [&] {
          if (!use_gpu) return std::pair{left.estimate(l, r), right.estimate(r, l)};
          return std::pair{gpu_left->estimate(l, r, {}, &gpu_error), gpu_right->estimate(r, l, {}, &gpu_error)};
        };
        sweepPair();  // first touch of the tables (and the GPU's shader compilation) not counted
        double wall = 1e9, cpu_time = 1e9;
        std::pair<xr::depth::SweepResult, xr::depth::SweepResult> result;
        for (int k = 0; k < repeats; ++k) {
          const double w0 = wallSeconds(), c0 = threadCpuSeconds();
          result = sweepPair();
          wall = std::min(wall, 1e3 * (wallSeconds() - w0));
          cpu_time = std::min(cpu_time, 1e3 * (threadCpuSeconds() - c0));
        }
        t.wall_ms = std::max(t.wall_ms, wall);  // the worst scene's best of `repeats`
        t.cpu_ms = std::max(t.cpu_ms, cpu_time);
        t.matched += result.first.tiles_matched + result.second.tiles_matched;
        t.grids.push_back(result.first.inverse_depth);
      }
    }
    if (!gpu_error.empty()) out << "GPU sweep: " << gpu_error << "\n";
    // Float sums in another order move a cost in its 5th digit: where two hypotheses tie that
    // closely, the other may win (a tile of another depth), so the tiles apart are counted too.
    double differs = 0;
    int tiles_apart = 0, grid_tiles = 0;
    for (std::size_t i = 0; i < cpu.grids.size(); ++i)
      for (int row = 0; row < cpu.grids[i].rows(); ++row)
        for (int col = 0; col < cpu.grids[i].cols(); ++col) {
          const double d = std::abs(cpu.grids[i].at(row, col) - on_gpu.grids[i].at(row, col));
          differs = std::max(differs, d);
          tiles_apart += d > 0.01;
          ++grid_tiles;
        }
    const std::string tiles = formatNumber(tile_deg) + " deg";
    table.addRow({tiles, "CPU, one core", formatNumber(cpu.wall_ms), formatNumber(cpu.cpu_ms), std::to_string(cpu.matched), "-", "-"});
    table.addRow({tiles, "GPU (" + renderer.substr(0, renderer.find(' ')) + ")", formatNumber(on_gpu.wall_ms),
                  formatNumber(on_gpu.cpu_ms), std::to_string(on_gpu.matched), formatNumber(differs),
                  std::to_string(tiles_apart) + " of " + std::to_string(grid_tiles)});
    rows.push_back({{"tile_deg", tile_deg},
                    {"cpu_path_ms_per_pair_wall", cpu.wall_ms},
                    {"cpu_path_cpu_ms_per_pair", cpu.cpu_ms},
                    {"gpu_ms_per_pair_wall", on_gpu.wall_ms},
                    {"gpu_calling_thread_cpu_ms_per_pair", on_gpu.cpu_ms},
                    {"tiles_matched_cpu", cpu.matched},
                    {"tiles_matched_gpu", on_gpu.matched},
                    {"grid_max_difference_per_m", differs},
                    {"grid_tiles_apart_over_0_01_per_m", tiles_apart},
                    {"grid_tiles", grid_tiles}});
  }
  out << "\nThe sweep's pair costs on the GPU (" << renderer << "; the decision, the views and the fill stay on the CPU), both "
      << "cameras a pair, the worst of " << scenes.size() << " scenes, best of " << repeats << " runs:\n";
  table.print(out);
  if (renderer.find("llvmpipe") != std::string::npos)
    out << "llvmpipe runs the shader on this machine's CPU cores: these are not a GPU's figures\n";
  return {{"renderer", renderer}, {"settings", rows}};
}

}  // namespace telesphere::bench::depth_bench
