// SPDX-License-Identifier: MIT
/// @brief The operator side's depth (#35): a thread that takes the newest decoded stereo pair,
///        box-filters both luma planes down to the sweep's working size, runs the sphere sweep
///        with each camera as the reference (xr/depth/sphere_sweep.h), filters each grid over
///        time (inverse_depth_filter.h) and publishes both grids with each camera's
///        centre-weighted radius. It never delays a frame: offer() only swaps a pointer, the
///        renderer takes whatever estimate is newest, and pairs that come while a sweep runs are
///        skipped. The pair's planes are held only while they are filtered down (a few ms), not
///        during the sweep, so the upload ring gets its slots back.
///
///        Each camera's filtered-down images of the last seconds are kept with their poses
///        (T_robot_cam from the joints at capture): where the arm has moved the cameras since, up to
///        motion_views of them (default 2) go to the sweep as earlier views (another baseline, which decides a pattern
///        repeating along the pair's: sphere_sweep.h). The farthest across the optical axis within
///        reach, and the one nearest a quarter of its baseline: a short baseline has few aliases, a
///        long one a sharp peak. Where the arm has held the cameras still for longer than that history,
///        the newest image from each place it was at stays a candidate for motion_keep_s.
#pragma once

#include <array>
#include <condition_variable>
#include <deque>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "calib/system_calibration.h"
#include "shaders/egl_context.h"
#include "robot/link/depth_proxy.h"
#include "xr/depth/inverse_depth_filter.h"
#include "xr/depth/sphere_sweep.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::xr::frame_loop {

struct DepthWorkerOptions {
  int working_width = 480;         ///< the luma planes are box-filtered by the integer nearest to width / this
  double centre_sigma_deg = 5.0;   ///< the radius's centre weighting about each camera's optical axis
  depth::SphereSweepOptions sweep;
  depth::InverseDepthFilterOptions filter;
  /// Earlier views from the arm's motion: up to this many per camera (0: the pair alone).
  int motion_views = 2;
  double motion_history_s = 2.0;        ///< how long a swept image stays a candidate (capture time)
  /// Beyond that, the newest image from each place (camera centres motion_min_baseline_m apart)
  /// stays a candidate this long, for sweeps whose recent history has none within reach (the arm
  /// held still): the views' own check keeps a tile the pair's where the scene changed since.
  double motion_keep_s = 10.0;
  double motion_min_baseline_m = 0.005;  ///< camera centres closer than this across the optical axis add no baseline
  double motion_max_baseline_m = 0.15;   ///< nor farther apart than this (the view sees another scene)
  /// offer() sweeps the pair at once on the caller's thread and newest() has its estimate when it
  /// returns (the offline replay: the same estimates run after run); no thread of its own.
  bool on_caller_thread = false;
  /// The worker thread's nice value (Linux: per thread; raising it needs no privilege). Above the
  /// frame loop's 0 the scheduler gives the renderer, the decoder and the link the cores first
  /// where they share them with the sweep, which only makes the depth on show older.
  int thread_nice = 10;
  /// The pair's costs on the GPU (xr/depth/gpu_sweep_costs.h) through a GL context of the worker
  /// thread's own: the depth thread's CPU time falls to about a quarter. Where no context with
  /// compute shaders can be made, or a sweep there fails, the CPU from then on, and the stats say
  /// why. Not with on_caller_thread (a context of its own there would take the caller's place on
  /// its thread): the CPU, and the stats say so. The context is a GPU's (EglContext::
  /// createOnHardwareDevice): Mesa's llvmpipe would run the shader on these CPU cores, slower than
  /// the CPU path and beside the renderer, so it is taken only with gpu_software_ok (the tests).
  bool gpu = false;
  bool gpu_software_ok = false;
};

/// One published estimate: per camera (0 left, 1 right) its filtered grid and radius.
struct DepthEstimate {
  std::array<std::shared_ptr<const render::InverseDepthGrid>, 2> grid;
  std::array<double, 2> radius_m{1.0, 1.0};
  std::array<double, 2> matched_fraction{0.0, 0.0};  ///< tiles matched of those the camera sees
  std::uint64_t frame_sequence = 0;                  ///< the stereo frame's link sequence
  std::int64_t capture_ns = 0;                       ///< its capture time (robot clock)
  double sweep_ms = 0;                               ///< CPU ms of both sweeps and filters
  std::array<int, 2> motion_views{0, 0};             ///< earlier views each camera's sweep took
  std::array<double, 2> motion_baseline_m{0.0, 0.0};  ///< the longest of them (camera centres apart across the optical axis)
  std::array<int, 2> tiles_decided_by_motion{0, 0};   ///< tiles whose depth those views decided
  bool pair_costs_on_gpu = false;                     ///< the pair's costs came from the GPU
};

struct DepthWorkerStats {
  std::uint64_t offered = 0;    ///< pairs offered
  std::uint64_t estimated = 0;  ///< estimates published
  std::uint64_t skipped = 0;    ///< pairs replaced by a newer one before the worker took them
  double last_sweep_ms = 0;
  std::string last_error;       ///< why the last pair gave no estimate (empty when it did)
  /// With DepthWorkerOptions::gpu: why the sweep runs on the CPU instead (empty while on the GPU).
  std::string gpu_unavailable;
};

class DepthWorker {
 public:
  /// `calibration` needs two cameras and T_cam_l_cam_r; models are rescaled to each pair's size.
  explicit DepthWorker(calib::SystemCalibration calibration, DepthWorkerOptions options = {});
  ~DepthWorker();
  DepthWorker(const DepthWorker&) = delete;
  DepthWorker& operator=(const DepthWorker&) = delete;

  /// Hands the worker a new pair (any thread, never blocks; a pair of the sequence offered last is
  /// ignored). With on_caller_thread: sweeps it before returning.
  void offer(std::shared_ptr<const video::DecodedStereoFrame> frame);
  /// The newest estimate, null before the first.
  std::shared_ptr<const DepthEstimate> newest() const;
  DepthWorkerStats stats() const;

 private:
  struct Sweeps;
  void run();
  /// estimate() with its outcome in the stats (the worker thread, or offer() on_caller_thread).
  void sweep(const video::DecodedStereoFrame& frame);
  bool estimate(const video::DecodedStereoFrame& frame, std::string* error);

  const calib::SystemCalibration calibration_;
  const DepthWorkerOptions options_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::shared_ptr<const video::DecodedStereoFrame> pending_;
  std::uint64_t last_sequence_ = 0;
  bool any_offered_ = false;
  std::shared_ptr<const DepthEstimate> newest_;
  DepthWorkerStats stats_;
  bool quit_ = false;
  /// A camera's image as swept (filtered down) with its pose, for later sweeps' earlier views.
  struct SweptImage {
    std::vector<std::uint8_t> grey;
    Eigen::Isometry3d T_robot_cam = Eigen::Isometry3d::Identity();
    std::int64_t capture_ns = 0;
  };
  /// The earlier views for camera `side` now at T_robot_cam (its history, chosen by baseline; its
  /// kept images where the history has none within reach).
  std::vector<depth::EarlierView> earlierViews(int side, const Eigen::Isometry3d& T_robot_cam, std::int64_t capture_ns,
                                               double* longest_m) const;
  /// An image leaving camera `side`'s history joins its kept images, in place of any kept one
  /// within motion_min_baseline_m of it (one a place, the newest); the oldest and those older
  /// than motion_keep_s at `now_ns` leave.
  void keep(int side, SweptImage image, std::int64_t now_ns);
  /// The GPU's context and cost volumes, made on the worker thread at its first pair and released
  /// there when it ends (GL objects belong to the thread their context is current on).
  bool gpuWanted() const { return options_.gpu && !options_.on_caller_thread; }
  void releaseGpu();
  // Worker thread only.
  std::unique_ptr<gl::EglContext> gl_context_;
  bool gpu_tried_ = false;
  std::string gpu_failure_;  ///< why the GPU is not used again (no context, a GL error in a sweep)
  std::unique_ptr<Sweeps> sweeps_;
  std::array<std::deque<SweptImage>, 2> history_;
  std::array<std::deque<SweptImage>, 2> kept_;  ///< per camera, oldest first (keep())
  std::uint64_t history_calibration_ = 0;  ///< the calibration generation the history's poses were made with
  std::array<depth::InverseDepthFilter, 2> filters_;
  std::array<std::vector<std::uint8_t>, 2> grey_;
  std::thread thread_;
};

}  // namespace telesphere::xr::frame_loop
