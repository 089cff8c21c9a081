// SPDX-License-Identifier: MIT
/// @brief DepthWorker: the newest pair in, luma box-filtered down, both sweeps and filters, the
///        estimate out.
#include "xr/frame_loop/depth_worker.h"

#include <pthread.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <spdlog/spdlog.h>

#include "calib/camera_resolution.h"
#include "robot/link/link_pose.h"
#include "xr/depth/box_downscale.h"
#include "xr/depth/gpu_sweep_costs.h"

namespace telesphere::xr::frame_loop {
namespace {

/// A camera's history holds at most this many images (2 s at 32 Hz; the sweep is slower on this
/// kind of machine, so the age limit is what counts).
constexpr std::size_t kMaxHistoryImages = 64;
/// And at most this many kept images from earlier places (DepthWorker::keep; 0.13 MB each at the
/// sweep's 480 × 270).
constexpr std::size_t kMaxKeptImages = 8;

/// Whether an image captured at `captured_ns` is older than `seconds` at `now_ns`.
bool agedOut(std::int64_t captured_ns, std::int64_t now_ns, double seconds) {
  return now_ns - captured_ns > static_cast<std::int64_t>(seconds * 1e9);
}

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

}  // namespace

/// Both cameras' sweeps for one image size (built on the worker thread when the size appears).
struct DepthWorker::Sweeps {
  int source_width = 0, source_height = 0, factor = 1, width = 0, height = 0;
  std::unique_ptr<depth::SphereSweep> left, right;
  std::unique_ptr<depth::GpuSweepCosts> gpu_left, gpu_right;  ///< with the GPU: each sweep's cost volume there
  /// Frees the GPU's objects (with the worker's context current).
  void dropGpu() {
    gpu_left.reset();
    gpu_right.reset();
  }
};

DepthWorker::DepthWorker(calib::SystemCalibration calibration, DepthWorkerOptions options)
    : calibration_(std::move(calibration)),
      options_(options),
      filters_{depth::InverseDepthFilter(options.filter), depth::InverseDepthFilter(options.filter)} {
  if (options_.gpu && options_.on_caller_thread)
    stats_.gpu_unavailable = "the sweep runs on the caller's thread (the offline replay), whose GL context is its own";
  if (!options_.on_caller_thread) thread_ = std::thread([this] { run(); });
}

DepthWorker::~DepthWorker() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DepthWorker::offer(std::shared_ptr<const video::DecodedStereoFrame> frame) {
  if (!frame) return;
  {
    std::lock_guard lock(mutex_);
    // The same pair again (the renderer offers what it shows, every display frame): ignored. Only
    // its sequence is kept, not the pair (which would hold its upload slots).
    const std::uint64_t sequence = frame->frame.sequence();
    if (any_offered_ && sequence == last_sequence_) return;
    any_offered_ = true;
    last_sequence_ = sequence;
    ++stats_.offered;
    if (!options_.on_caller_thread) {
      if (pending_) ++stats_.skipped;
      pending_ = std::move(frame);
    }
  }
  if (options_.on_caller_thread) return sweep(*frame);
  wake_.notify_one();
}

std::shared_ptr<const DepthEstimate> DepthWorker::newest() const {
  std::lock_guard lock(mutex_);
  return newest_;
}

DepthWorkerStats DepthWorker::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void DepthWorker::run() {
  // Named for top, perf and the tests; niced below the frame loop's threads, never above where
  // the process already runs (a process started nicer stays as nice).
  pthread_setname_np(pthread_self(), "ts-depth");
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int inherited = getpriority(PRIO_PROCESS, tid);
  if (errno == 0 && inherited < options_.thread_nice && setpriority(PRIO_PROCESS, tid, options_.thread_nice) != 0)
    spdlog::warn("depth: the worker thread keeps its priority (setpriority nice {}: {})", options_.thread_nice, std::strerror(errno));
  for (;;) {
    std::shared_ptr<const video::DecodedStereoFrame> frame;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return quit_ || pending_; });
      if (quit_) break;
      frame = std::move(pending_);
    }
    sweep(*frame);
  }
  releaseGpu();
}

void DepthWorker::releaseGpu() {
  if (sweeps_) {
    sweeps_->dropGpu();
  }
  gl_context_.reset();
}

void DepthWorker::sweep(const video::DecodedStereoFrame& frame) {
  std::string error;
  const bool ok = estimate(frame, &error);
  std::lock_guard lock(mutex_);
  stats_.last_error = ok ? std::string() : error;
}

bool DepthWorker::estimate(const video::DecodedStereoFrame& frame, std::string* error) {
  if (calibration_.cameras.size() < 2 || !calibration_.T_cam_l_cam_r) {
    *error = "the calibration has no stereo pair";
    return false;
  }
  if (!frame.left || !frame.right || frame.left->width != frame.right->width || frame.left->height != frame.right->height) {
    *error = "the pair's images differ in size or are missing";
    return false;
  }
  const double cpu0 = threadCpuMs();
  const int source_width = frame.left->width, source_height = frame.left->height;
  if (!sweeps_ || sweeps_->source_width != source_width || sweeps_->source_height != source_height) {
    auto s = std::make_unique<Sweeps>();
    s->source_width = source_width;
    s->source_height = source_height;
    s->factor = std::max(1, static_cast<int>(std::lround(static_cast<double>(source_width) / std::max(options_.working_width, 16))));
    s->width = source_width / s->factor;
    s->height = source_height / s->factor;
    if (s->width < 16 || s->height < 16) {
      *error = "images of " + std::to_string(source_width) + "x" + std::to_string(source_height) + " are too small for depth";
      return false;
    }
    // A block of factor × factor pixels maps like a pixel of the image scaled by 1/factor
    // (atResolution's convention, pixel centres at integers).
    // The models at the frames' size, cropped to whole blocks (the intrinsics stay), then at 1/factor.
    std::array<std::optional<calib::CameraCalibration>, 2> at;
    for (int i = 0; i < 2; ++i) {
      at[i] = calib::atResolution(calibration_.cameras[i], source_width, source_height, error);
      if (!at[i]) return false;
      at[i]->width = s->width * s->factor;
      at[i]->height = s->height * s->factor;
      at[i] = calib::atResolution(*at[i], s->width, s->height, error);
      if (!at[i]) return false;
    }
    const Eigen::Isometry3d& T_l_r = *calibration_.T_cam_l_cam_r;
    s->left = std::make_unique<depth::SphereSweep>(at[0]->camera, s->width, s->height, at[1]->camera, s->width, s->height,
                                                   T_l_r.inverse(), options_.sweep);
    s->right = std::make_unique<depth::SphereSweep>(at[1]->camera, s->width, s->height, at[0]->camera, s->width, s->height,
                                                    T_l_r, options_.sweep);
    if (gpuWanted()) {
      // The GPU's cost volumes for these sweeps (the context at the first pair, once).
      std::string why;
      if (!gpu_tried_) {
        gpu_tried_ = true;
        std::string error;
        gl_context_ = gl::EglContext::createOnHardwareDevice(&error);
        if (!gl_context_ && options_.gpu_software_ok) gl_context_ = gl::EglContext::createSurfaceless(&error);
        if (!gl_context_)
          gpu_failure_ = options_.gpu_software_ok
                             ? "no GL 4.5 context: " + error
                             : error + "; a software GL (Mesa's llvmpipe) would sum on these CPU cores, slower than the CPU path";
      }
      if (!gpu_failure_.empty()) {
        why = gpu_failure_;
      } else {
        if (sweeps_) {  // the last size's, while the context is current
          sweeps_->dropGpu();
        }
        s->gpu_left = depth::GpuSweepCosts::create(*s->left, &why);
        if (s->gpu_left) s->gpu_right = depth::GpuSweepCosts::create(*s->right, &why);
        if (!s->gpu_right) s->gpu_left.reset();
      }
      std::lock_guard lock(mutex_);
      stats_.gpu_unavailable = s->gpu_right ? std::string() : why;
      if (s->gpu_right)
        spdlog::info("depth: the sweep's pair costs on the GPU ({})", gl_context_->renderer());
      else
        spdlog::warn("depth: the sweep's pair costs on the CPU, not the GPU: {}", why);
    }
    sweeps_ = std::move(s);
    for (int i = 0; i < 2; ++i) history_[i].clear(), kept_[i].clear();  // images of another size
  }
  const Sweeps& s = *sweeps_;
  int w = 0, h = 0;
  depth::boxDownscale(frame.left->yPlane(), source_width, source_height, source_width, s.factor, grey_[0], &w, &h);
  depth::boxDownscale(frame.right->yPlane(), source_width, source_height, source_width, s.factor, grey_[1], &w, &h);
  const depth::GreyImage left{grey_[0].data(), w, h, w}, right{grey_[1].data(), w, h, w};
  // Each camera's pose at capture, where the joints gave it (a fixed calibrated pose says nothing
  // about motion), from the calibration the history was made with.
  const link::proto::CameraImage* images[2] = {&frame.frame.left(), &frame.frame.right()};
  if (frame.frame.calibration_generation() != history_calibration_) {
    for (int i = 0; i < 2; ++i) history_[i].clear(), kept_[i].clear();
    history_calibration_ = frame.frame.calibration_generation();
  }
  std::array<std::optional<Eigen::Isometry3d>, 2> T_robot_cam;
  for (int i = 0; i < 2; ++i)
    if (options_.motion_views > 0 && images[i]->pose_source() == link::proto::POSE_SOURCE_JOINT_BUFFER && images[i]->has_t_robot_cam()) {
      const Eigen::Isometry3d T = link::fromLinkPose(images[i]->t_robot_cam());
      if (T.matrix().allFinite()) T_robot_cam[i] = T;
    }
  const std::int64_t capture_ns = frame.frame.stamps().capture_ns();
  // The history before the views are chosen: what has left its 2 s is kept already (the views
  // point into both; nothing moves until this pair's images join, after the sweep).
  for (int i = 0; i < 2; ++i) {
    std::deque<SweptImage>& h = history_[i];
    // Time went back (a replay restarted): neither the history nor the kept images are earlier.
    if ((!h.empty() && h.back().capture_ns >= capture_ns) || (!kept_[i].empty() && kept_[i].back().capture_ns >= capture_ns))
      h.clear(), kept_[i].clear();
    while (!h.empty() && agedOut(h.front().capture_ns, capture_ns, options_.motion_history_s)) {
      keep(i, std::move(h.front()), capture_ns);
      h.pop_front();
    }
  }
  std::array<std::vector<depth::EarlierView>, 2> earlier;
  std::array<double, 2> longest{0.0, 0.0};
  for (int i = 0; i < 2; ++i)
    if (T_robot_cam[i]) earlier[i] = earlierViews(i, *T_robot_cam[i], capture_ns, &longest[i]);
  depth::SweepResult results[2];
  bool on_gpu = false;
  if (s.gpu_left && s.gpu_right) {
    std::string why;
    results[0] = s.gpu_left->estimate(left, right, earlier[0], &why);
    if (why.empty()) results[1] = s.gpu_right->estimate(right, left, earlier[1], &why);
    on_gpu = why.empty();
    if (!on_gpu) {  // a GL error: the CPU from here on (another image size too), and the stats say why
      spdlog::warn("depth: the GPU's pair costs failed, the CPU from now on: {}", why);
      gpu_failure_ = why;
      sweeps_->dropGpu();
      std::lock_guard lock(mutex_);
      stats_.gpu_unavailable = why;
    }
  }
  if (!on_gpu) {
    results[0] = s.left->estimate(left, right, earlier[0]);
    results[1] = s.right->estimate(right, left, earlier[1]);
  }
  // What the views were, before the history they point into changes.
  std::array<int, 2> views_taken{static_cast<int>(earlier[0].size()), static_cast<int>(earlier[1].size())};
  // This pair's images join the history (not where rows were concealed or grey: not what the camera saw).
  for (int i = 0; i < 2; ++i) {
    std::deque<SweptImage>& h = history_[i];
    if (!T_robot_cam[i] || frame.rows_concealed != 0 || frame.rows_grey != 0) continue;
    if (h.size() >= kMaxHistoryImages) {  // what leaves by number may stay as the last image from its place
      keep(i, std::move(h.front()), capture_ns);
      h.pop_front();
    }
    h.push_back({grey_[i], *T_robot_cam[i], capture_ns});
  }

  auto out = std::make_shared<DepthEstimate>();
  out->frame_sequence = frame.frame.sequence();
  out->capture_ns = capture_ns;
  for (int i = 0; i < 2; ++i) {
    const render::InverseDepthGrid& filtered = filters_[i].update(results[i].inverse_depth, results[i].confidence, out->capture_ns);
    out->grid[i] = std::make_shared<const render::InverseDepthGrid>(filtered);
    out->radius_m[i] = render::centreWeightedRadius(filtered, {0, 0, 1}, options_.centre_sigma_deg * std::numbers::pi / 180.0);
    out->matched_fraction[i] = results[i].tiles_seen ? static_cast<double>(results[i].tiles_matched) / results[i].tiles_seen : 0.0;
    out->motion_views[i] = views_taken[i];
    out->motion_baseline_m[i] = longest[i];
    out->tiles_decided_by_motion[i] = results[i].tiles_decided_by_motion;
  }
  out->pair_costs_on_gpu = on_gpu;
  out->sweep_ms = threadCpuMs() - cpu0;
  std::lock_guard lock(mutex_);
  newest_ = std::move(out);
  ++stats_.estimated;
  stats_.last_sweep_ms = newest_->sweep_ms;
  return true;
}

std::vector<depth::EarlierView> DepthWorker::earlierViews(int side, const Eigen::Isometry3d& T_robot_cam, std::int64_t capture_ns,
                                                          double* longest_m) const {
  const Sweeps& s = *sweeps_;
  // Candidates: recent images whose camera centre lies within reach of where it is now, ranked by
  // how far across the optical axis; where the recent images offer none (the arm held still), the
  // last images from elsewhere.
  std::vector<std::pair<double, const SweptImage*>> reach;
  const auto addWithinReach = [&](const std::deque<SweptImage>& images, double max_age_s) {
    for (const SweptImage& image : images) {
      if (agedOut(image.capture_ns, capture_ns, max_age_s) || image.capture_ns >= capture_ns) continue;
      // The baseline across the optical axis (in the camera's frame now): what gives the middle of
      // the view parallax. A motion along the axis leaves the view's middle at the focus of
      // expansion (telesphere-bench depth: 5 and 1 cm forward decide the stripes' middle least).
      const Eigen::Vector3d moved = T_robot_cam.linear().transpose() * (image.T_robot_cam.translation() - T_robot_cam.translation());
      const double across = std::hypot(moved.x(), moved.y());
      if (across >= options_.motion_min_baseline_m && moved.norm() <= options_.motion_max_baseline_m) reach.emplace_back(across, &image);
    }
  };
  addWithinReach(history_[side], options_.motion_history_s);
  if (reach.empty()) addWithinReach(kept_[side], options_.motion_keep_s);
  std::vector<const SweptImage*> chosen;
  if (!reach.empty()) {
    const auto farthest = std::max_element(reach.begin(), reach.end());
    chosen.push_back(farthest->second);
    *longest_m = farthest->first;
    // Then the one nearest a quarter of that baseline (at most half of it), and so on.
    double target = farthest->first / 4.0;
    while (static_cast<int>(chosen.size()) < options_.motion_views) {
      const std::pair<double, const SweptImage*>* best = nullptr;
      for (const auto& candidate : reach)
        if (candidate.first <= 2.0 * target && std::find(chosen.begin(), chosen.end(), candidate.second) == chosen.end() &&
            (!best || std::abs(candidate.first - target) < std::abs(best->first - target)))
          best = &candidate;
      if (!best) break;
      chosen.push_back(best->second);
      target = best->first / 4.0;
    }
  }
  std::vector<depth::EarlierView> views;
  for (const SweptImage* image : chosen)
    views.push_back({{image->grey.data(), s.width, s.height, s.width}, image->T_robot_cam.inverse() * T_robot_cam});
  return views;
}

void DepthWorker::keep(int side, SweptImage image, std::int64_t now_ns) {
  std::deque<SweptImage>& kept = kept_[side];
  const auto far = [&](const SweptImage& k) {
    return (k.T_robot_cam.translation() - image.T_robot_cam.translation()).norm() >= options_.motion_min_baseline_m;
  };
  kept.erase(std::remove_if(kept.begin(), kept.end(),
                            [&](const SweptImage& k) {
                              return !far(k) || agedOut(k.capture_ns, now_ns, options_.motion_keep_s);
                            }),
             kept.end());
  if (agedOut(image.capture_ns, now_ns, options_.motion_keep_s)) return;
  if (kept.size() >= kMaxKeptImages) kept.pop_front();
  kept.push_back(std::move(image));
}

}  // namespace telesphere::xr::frame_loop
