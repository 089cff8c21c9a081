// SPDX-License-Identifier: MIT
/// @brief The depth bench's stereo sweeps (`telesphere-bench depth`, #35): both cameras' sweeps for
///        one setting, a pair through them with the left grid's error against the truth, and the
///        stereo proxies (one radius, the grid) with the figures every table reports for them.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/depth_bench_scenes.h"
#include "app/bench/depth_eye_errors.h"
#include "calib/system_calibration.h"
#include "xr/depth/sphere_sweep.h"

namespace telesphere::bench::depth_bench {

inline constexpr double kCentreSigmaDeg = 5.0;  ///< the single radius's centre weighting (and twice it)

/// Both cameras' sweeps for one setting (tables built once; the first pair is swept once untimed,
/// so that the tables' first touch is not counted against every frame after it).
struct StereoSweeps {
  std::string name;
  xr::depth::SphereSweep left, right;
  bool warm = false;
};

StereoSweeps makeSweeps(const std::string& name, const calib::SystemCalibration& rig, int width, int height,
                        const xr::depth::SphereSweepOptions& options);

/// One pair through both sweeps: the left camera's grid, the CPU time of both, and the grid's
/// inverse-depth error over the tiles the left camera sees against the truth at the same tiles.
struct StereoDepth {
  xr::depth::SweepResult left;
  double ms = 0;
  int matched = 0, seen = 0, decided_by_motion = 0;
  std::vector<double> inverse_depth_error;
};

/// The tiles of `grid` whose centre `camera` sees inside its width × height image.
std::vector<std::pair<int, int>> seenTiles(const xr::render::InverseDepthGrid& grid, const calib::CameraCalibration& camera,
                                           int width, int height);

/// How often the tables that report a sweep's time sweep each pair: the median of these (one pair's
/// time moves by up to 25 % between runs on a shared VM).
inline constexpr int kTimedRuns = 5;

/// `earlier`: per camera (left, right), its views from earlier poses of the rig (SphereSweep::estimate).
/// The pair is swept `timed_runs` times and `ms` is the median of those times (the grids are the
/// same every time).
StereoDepth sweepPair(StereoSweeps& sweeps, const StereoGrey& pair, int width, int height, const robot::cameras::SceneView& camera,
                      const calib::CameraCalibration& left_camera,
                      const std::array<std::vector<xr::depth::EarlierView>, 2>& earlier = {}, int timed_runs = 1);

/// The radius (σ kCentreSigmaDeg) and the grid from a sweep's left grid.
std::vector<Proxy> stereoProxies(const StereoDepth& depth);

/// A sweep's figures with its stereo proxies (stereoProxies order, moving eye errors evaluated):
/// matched tiles, inverse-depth error, the radius and its fovea error, the grid's errors.
nlohmann::json stereoFigures(const StereoDepth& depth, const std::vector<Proxy>& proxies);

}  // namespace telesphere::bench::depth_bench
