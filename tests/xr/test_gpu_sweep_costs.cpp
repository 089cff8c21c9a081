// SPDX-License-Identifier: MIT
/// @brief GpuSweepCosts (xr/depth/gpu_sweep_costs.h) on a real GL 4.5 context (Mesa's llvmpipe
///        here, any GPU's driver elsewhere) against the CPU's sweep on the same rendered pair, a
///        textured room with a near box and the board of stripes: every cost of a textured tile's
///        usable hypothesis within 2e-5 of the CPU's (float sums in another order), and the whole
///        sweep's grid the CPU's (the same tiles matched, inverse depths within 1e-4 1/m), at 4°
///        and at 2° tiles (four times the work groups), with earlier views too; an image of
///        another size or another sweep's patches are refused with a reason, not computed. The
///        depth worker with --depth-gpu publishes the CPU worker's estimates, the rig moving; without
///        a GPU it sums on the CPU and says why, rather than on Mesa's llvmpipe (unless allowed).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <thread>
#include <string>
#include <vector>

#include "app/bench/prerendered_frames.h"
#include "shaders/egl_context.h"
#include "tests/xr/scene_grey.h"
#include "tests/xr/stripes_room.h"
#include "xr/depth/gpu_sweep_costs.h"
#include "xr/frame_loop/depth_worker.h"

namespace telesphere::xr {
namespace {

constexpr int kGpuWidth = 480, kGpuHeight = 270;

/// The room with a 20 cm box 0.5 m ahead and the board of stripes beside it, 1.2 m ahead and 0.9 m
/// to the right: near, far and repetitive in one pair.
std::shared_ptr<robot::cameras::SyntheticScene> gpuTestScene() {
  auto scene = test_scenes::room(true);
  robot::cameras::SurfaceStyle style;
  Eigen::Isometry3d T_world_box = Eigen::Isometry3d::Identity();
  T_world_box.translation() = Eigen::Vector3d(0.0, 0.0, 0.6);
  scene->addBox("box", robot::cameras::fixedPose(T_world_box), Eigen::Vector3d(0.1, 0.1, 0.1), style);
  test_scenes::addStripesBoard(*scene, Eigen::Vector3d(0.9, 0.0, 1.2));
  return scene;
}

std::vector<std::uint8_t> gpuTestGrey(const std::shared_ptr<robot::cameras::SyntheticScene>& scene, const Eigen::Isometry3d& T_world_cam) {
  return test_scenes::greyImage(scene, bench::simulatedLens(kGpuWidth, kGpuHeight).camera, kGpuWidth, kGpuHeight, T_world_cam);
}

TEST(GpuSweepCosts, TheGpusCostsAndGridAreTheCpus) {
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  ASSERT_TRUE(context) << "no GL 4.5 context: " << error;
  const auto scene = gpuTestScene();
  const Eigen::Isometry3d T_l_r(Eigen::Translation3d(0.064, 0.0, 0.0));
  const std::vector<std::uint8_t> left = gpuTestGrey(scene, Eigen::Isometry3d::Identity()), right = gpuTestGrey(scene, T_l_r);
  // An earlier view: the rig 3 cm to the left of where it is now.
  const Eigen::Isometry3d T_world_then(Eigen::Translation3d(-0.03, 0.0, 0.0));
  const std::vector<std::uint8_t> left_then = gpuTestGrey(scene, T_world_then);
  const depth::GreyImage l{left.data(), kGpuWidth, kGpuHeight, kGpuWidth}, r{right.data(), kGpuWidth, kGpuHeight, kGpuWidth};
  const std::vector<depth::EarlierView> earlier = {{{left_then.data(), kGpuWidth, kGpuHeight, kGpuWidth}, T_world_then.inverse()}};
  const calib::GenericCamera lens = bench::simulatedLens(kGpuWidth, kGpuHeight).camera;
  for (const double tile_deg : {4.0, 2.0}) {
    SCOPED_TRACE("tiles of " + std::to_string(tile_deg) + " deg");
    depth::SphereSweepOptions options;
    options.tile_deg = tile_deg;
    const depth::SphereSweep sweep(lens, kGpuWidth, kGpuHeight, lens, kGpuWidth, kGpuHeight, T_l_r.inverse(), options);
    const auto gpu = depth::GpuSweepCosts::create(sweep, &error);
    ASSERT_TRUE(gpu) << error;
    EXPECT_EQ(gpu->tableBytes(), sweep.otherTaps().size() * sizeof(depth::BilinearTap));

    const depth::SphereSweep::ReferencePatches patches = sweep.referencePatches(l);
    const std::vector<float> cpu_costs = sweep.pairCosts(patches, r);
    std::vector<float> gpu_costs;
    ASSERT_TRUE(gpu->pairCosts(patches, r, gpu_costs, &error)) << error;
    ASSERT_EQ(gpu_costs.size(), cpu_costs.size());
    const std::size_t hypotheses = static_cast<std::size_t>(options.hypotheses);
    const std::size_t samples = static_cast<std::size_t>(sweep.samplesPerTile());
    // The double-precision reference: the same integer bilinear samples, the reference patch's
    // float values made exactly mean-free, everything summed in double. Against it: the costs of
    // patches with texture (σ of the other patch ≥ 0.5 grey) closely, and those of nearly flat
    // ones (where float's Σb² − (Σb)²/n cancels, and the cost is about 1 whoever computes it) loosely.
    int compared = 0, flat = 0;
    double worst_gpu = 0, worst_cpu = 0, worst_flat = 0;
    for (std::size_t i = 0; i < cpu_costs.size(); ++i) {
      const std::size_t tile = i / hypotheses;
      if (!patches.textured[tile]) {
        EXPECT_TRUE(std::isinf(gpu_costs[i])) << "an untextured tile's cost, " << i;
        continue;
      }
      if (std::isinf(cpu_costs[i])) continue;  // an unusable hypothesis: decide() ignores what the GPU holds there
      double mean_a = 0;
      for (std::size_t s = 0; s < samples; ++s) mean_a += patches.a[tile * samples + s];
      mean_a /= static_cast<double>(samples);
      double b = 0, bb = 0, ab = 0, aa = 0;
      for (std::size_t s = 0; s < samples; ++s) {
        const double v = depth::tapGrey(right.data(), kGpuWidth, sweep.otherTaps()[i * samples + s]);
        const double av = patches.a[tile * samples + s] - mean_a;
        b += v;
        bb += v * v;
        ab += av * v;
        aa += av * av;
      }
      const double var_b = bb - b * b / static_cast<double>(samples);
      const double want = 1.0 - ab / std::sqrt(aa * var_b);
      if (var_b < 0.25 * static_cast<double>(samples)) {
        worst_flat = std::max({worst_flat, std::abs(gpu_costs[i] - want), std::abs(cpu_costs[i] - want)});
        ++flat;
        continue;
      }
      worst_gpu = std::max(worst_gpu, std::abs(gpu_costs[i] - want));
      worst_cpu = std::max(worst_cpu, std::abs(cpu_costs[i] - want));
      ++compared;
    }
    EXPECT_GT(compared, 30000);
    EXPECT_LE(worst_gpu, 1e-4);
    EXPECT_LE(worst_cpu, 1e-4);
    EXPECT_LE(worst_flat, 1e-2);
    std::cout << "tiles " << tile_deg << " deg, against the double reference: " << compared << " costs, worst GPU " << worst_gpu
              << ", CPU " << worst_cpu << "; " << flat << " nearly flat, worst " << worst_flat << "\n";

    for (const bool with_views : {false, true}) {
      SCOPED_TRACE(with_views ? "with an earlier view" : "the pair alone");
      const std::vector<depth::EarlierView> views = with_views ? earlier : std::vector<depth::EarlierView>{};
      const depth::SweepResult on_cpu = sweep.estimate(l, r, views);
      const depth::SweepResult on_gpu = gpu->estimate(l, r, views, &error);
      EXPECT_TRUE(error.empty()) << error;
      ASSERT_GT(on_cpu.tiles_matched, on_cpu.tiles_seen / 2);
      EXPECT_EQ(on_gpu.tiles_seen, on_cpu.tiles_seen);
      EXPECT_EQ(on_gpu.tiles_matched, on_cpu.tiles_matched);
      EXPECT_EQ(on_gpu.tiles_ambiguous, on_cpu.tiles_ambiguous);
      EXPECT_EQ(on_gpu.tiles_decided_by_motion, on_cpu.tiles_decided_by_motion);
      if (with_views) {
        EXPECT_GT(on_cpu.tiles_decided_by_motion, 0);
      }
      const render::InverseDepthGrid& a = on_cpu.inverse_depth;
      const render::InverseDepthGrid& b = on_gpu.inverse_depth;
      int off = 0;
      for (int row = 0; row < a.rows(); ++row)
        for (int col = 0; col < a.cols(); ++col) off += std::abs(a.at(row, col) - b.at(row, col)) > 1e-4F;
      EXPECT_EQ(off, 0) << "tiles whose inverse depth differs by more than 1e-4 1/m";
    }
  }
}

TEST(GpuSweepCosts, RefusesAnImageOfAnotherSizeAndAnotherSweepsPatches) {
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  ASSERT_TRUE(context) << "no GL 4.5 context: " << error;
  const calib::GenericCamera lens = bench::simulatedLens(kGpuWidth, kGpuHeight).camera;
  const Eigen::Isometry3d T_r_l(Eigen::Translation3d(-0.064, 0.0, 0.0));
  const depth::SphereSweep sweep(lens, kGpuWidth, kGpuHeight, lens, kGpuWidth, kGpuHeight, T_r_l);
  const auto gpu = depth::GpuSweepCosts::create(sweep, &error);
  ASSERT_TRUE(gpu) << error;
  const std::vector<std::uint8_t> image(static_cast<std::size_t>(kGpuWidth) * kGpuHeight, 128), small(100 * 50, 128);
  const depth::GreyImage full{image.data(), kGpuWidth, kGpuHeight, kGpuWidth};
  const depth::SphereSweep::ReferencePatches patches = sweep.referencePatches(full);
  std::vector<float> costs;
  EXPECT_FALSE(gpu->pairCosts(patches, {small.data(), 100, 50, 100}, costs, &error));
  EXPECT_NE(error.find("100x50"), std::string::npos) << error;
  EXPECT_FALSE(gpu->pairCosts({}, full, costs, &error));
  EXPECT_NE(error.find("patches"), std::string::npos) << error;
  error.clear();
  const depth::SweepResult none = gpu->estimate({small.data(), 100, 50, 100}, full, {}, &error);
  EXPECT_EQ(none.tiles_matched, 0);
  EXPECT_FALSE(error.empty());
  // The CPU's steps refuse what is not theirs too: a reference image of another size, another
  // sweep's patches (nothing read past either).
  const std::vector<float> cpu_costs = sweep.pairCosts(patches, full);
  EXPECT_EQ(sweep.decide({small.data(), 100, 50, 100}, patches, cpu_costs).tiles_seen, sweep.tileCount());
  EXPECT_EQ(sweep.decide({small.data(), 100, 50, 100}, patches, cpu_costs).tiles_matched, 0);
  depth::SphereSweep::ReferencePatches short_patches = patches;
  short_patches.a.resize(10);
  EXPECT_FALSE(sweep.fits(short_patches));
  EXPECT_EQ(sweep.decide(full, short_patches, cpu_costs).tiles_matched, 0);
  const std::vector<float> none_costs = sweep.pairCosts(short_patches, full);
  EXPECT_TRUE(std::all_of(none_costs.begin(), none_costs.end(), [](float c) { return std::isinf(c); }));
  // A flat grey pair: every tile without texture, nothing matched, no error.
  error.clear();
  const depth::SweepResult flat = gpu->estimate(full, full, {}, &error);
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_EQ(flat.tiles_matched, 0);
}

/// A pair of the test scene at 960 × 540 (the worker's working size is half of it) with the rig's
/// left camera at p_robot_rig, each camera's pose from the joints.
std::shared_ptr<video::DecodedStereoFrame> gpuTestPair(const std::shared_ptr<robot::cameras::SyntheticScene>& scene,
                                                       const calib::SystemCalibration& rig, const Eigen::Vector3d& p_robot_rig,
                                                       std::uint64_t sequence) {
  return test_scenes::rigPairAt(scene, rig, 960, 540, p_robot_rig, sequence);
}

TEST(GpuSweepCosts, TheDepthWorkerOnTheGpuPublishesTheCpuWorkersEstimates) {
  using namespace std::chrono_literals;
  const auto scene = gpuTestScene();
  const calib::SystemCalibration rig = bench::simulatedRig(3840, 2160);
  frame_loop::DepthWorkerOptions gpu_options, cpu_options, caller_options;
  gpu_options.gpu = true;  // its own thread, its own GL context there
  gpu_options.gpu_software_ok = true;  // llvmpipe, where there is no GPU
  cpu_options.on_caller_thread = true;
  caller_options.on_caller_thread = true;
  caller_options.gpu = true;  // not on the caller's thread: the CPU
  frame_loop::DepthWorker on_gpu(rig, gpu_options), on_cpu(rig, cpu_options), on_caller(rig, caller_options);
  // The rig coming in from 4 cm to the left: the later pairs take the earlier ones as views.
  const Eigen::Vector3d positions[3] = {{-0.04, 0.0, 0.0}, {-0.02, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  for (std::uint64_t sequence = 1; sequence <= 3; ++sequence) {
    SCOPED_TRACE("pair " + std::to_string(sequence));
    const auto pair = gpuTestPair(scene, rig, positions[sequence - 1], sequence);
    on_cpu.offer(pair);
    on_caller.offer(pair);
    on_gpu.offer(pair);
    std::shared_ptr<const frame_loop::DepthEstimate> gpu;
    for (int i = 0; i < 500 && !((gpu = on_gpu.newest()) && gpu->frame_sequence == sequence); ++i) std::this_thread::sleep_for(20ms);
    ASSERT_TRUE(gpu && gpu->frame_sequence == sequence) << on_gpu.stats().last_error;
    const auto cpu = on_cpu.newest();
    ASSERT_TRUE(cpu);
    EXPECT_TRUE(gpu->pair_costs_on_gpu) << on_gpu.stats().gpu_unavailable;
    EXPECT_TRUE(on_gpu.stats().gpu_unavailable.empty()) << on_gpu.stats().gpu_unavailable;
    EXPECT_FALSE(cpu->pair_costs_on_gpu);
    EXPECT_FALSE(on_caller.newest()->pair_costs_on_gpu);
    EXPECT_NE(on_caller.stats().gpu_unavailable.find("caller's thread"), std::string::npos) << on_caller.stats().gpu_unavailable;
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(gpu->radius_m[i], cpu->radius_m[i], 1e-4);
      EXPECT_EQ(gpu->matched_fraction[i], cpu->matched_fraction[i]);
      EXPECT_EQ(gpu->motion_views[i], cpu->motion_views[i]);
      EXPECT_EQ(gpu->tiles_decided_by_motion[i], cpu->tiles_decided_by_motion[i]);
      const render::InverseDepthGrid &a = *gpu->grid[i], &b = *cpu->grid[i];
      float worst = 0;
      for (int k = 0; k < a.rows() * a.cols(); ++k) worst = std::max(worst, std::abs(a.data()[k] - b.data()[k]));
      EXPECT_LE(worst, 1e-4F) << "camera " << i;
    }
    if (sequence == 3) {
      EXPECT_GT(cpu->motion_views[0], 0);  // the views took part
    }
  }
}

TEST(GpuSweepCosts, WithoutAGpuTheWorkerSumsOnTheCpuAndSaysWhyRatherThanOnLlvmpipe) {
  // A context for work that must not fall to the CPU's cores is a GPU's or none.
  std::string error;
  const auto hardware = gl::EglContext::createOnHardwareDevice(&error);
  if (hardware) {
    EXPECT_FALSE(hardware->software()) << hardware->renderer();
  } else {
    EXPECT_NE(error.find("GPU"), std::string::npos) << error;
  }
  const bool gpu_here = hardware != nullptr;
  {
    const auto any = gl::EglContext::createSurfaceless(&error);
    ASSERT_TRUE(any) << error;
    if (any->renderer().find("llvmpipe") != std::string::npos) {
      EXPECT_TRUE(any->software());
    }
  }
  // The worker with --depth-gpu but not --depth-gpu-software: on a GPU where there is one, else the
  // CPU with the reason (here: Mesa's llvmpipe only).
  const auto scene = gpuTestScene();
  const calib::SystemCalibration rig = bench::simulatedRig(3840, 2160);
  frame_loop::DepthWorkerOptions options;
  options.gpu = true;
  frame_loop::DepthWorker worker(rig, options);
  worker.offer(gpuTestPair(scene, rig, Eigen::Vector3d::Zero(), 1));
  std::shared_ptr<const frame_loop::DepthEstimate> estimate;
  for (int i = 0; i < 500 && !(estimate = worker.newest()); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(estimate) << worker.stats().last_error;
  EXPECT_EQ(estimate->pair_costs_on_gpu, gpu_here) << worker.stats().gpu_unavailable;
  if (!gpu_here) {
    EXPECT_NE(worker.stats().gpu_unavailable.find("software"), std::string::npos) << worker.stats().gpu_unavailable;
    EXPECT_GT(estimate->matched_fraction[0], 0.5);  // the CPU's sweep, as ever
  }
}

}  // namespace
}  // namespace telesphere::xr
