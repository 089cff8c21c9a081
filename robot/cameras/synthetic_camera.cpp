// SPDX-License-Identifier: MIT
/// @brief The rendered camera (see synthetic_camera.h).
#include "robot/cameras/synthetic_camera.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "calib/debug_assert.h"

namespace telesphere::robot::cameras {
namespace {

constexpr int kSyntheticRowsPerChunk = 8;

/// floor(a / b) for b > 0.
std::int64_t syntheticFloorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// Runs body(row_begin, row_end) over [0, rows) in chunks on `threads` threads (the caller's
/// included); stops handing out chunks once `stop()` says so.
void syntheticParallelRows(int rows, int threads, const std::function<bool()>& stop,
                           const std::function<void(int, int)>& body) {
  std::atomic<int> next{0};
  const auto worker = [&] {
    for (;;) {
      const int begin = next.fetch_add(kSyntheticRowsPerChunk);
      if (begin >= rows || stop()) return;
      body(begin, std::min(rows, begin + kSyntheticRowsPerChunk));
    }
  };
  std::vector<std::thread> helpers;
  for (int i = 1; i < threads; ++i) helpers.emplace_back(worker);
  worker();
  for (std::thread& t : helpers) t.join();
}

}  // namespace

SyntheticCamera::SyntheticCamera(const calib::GenericCamera& camera, int width, int height,
                                 std::shared_ptr<const SyntheticScene> scene, PoseAtTime T_world_cam_at,
                                 const clock::Clock& clock, SyntheticCameraOptions options)
    : camera_(camera),
      width_(width),
      height_(height),
      scene_(std::move(scene)),
      T_world_cam_at_(std::move(T_world_cam_at)),
      clock_(clock),
      options_(std::move(options)),
      period_ns_(0) {
  TS_ASSERT(width_ > 0 && width_ <= 32768 && height_ > 0 && height_ <= 32768, width_, height_);
  TS_ASSERT(options_.fps > 0.0 && std::isfinite(options_.fps), options_.fps);
  TS_ASSERT(options_.supersampling >= 1 && options_.supersampling <= 8, options_.supersampling);
  TS_ASSERT(options_.threads >= 1, options_.threads);
  TS_ASSERT(options_.transfer_ns >= 0, options_.transfer_ns);
  TS_ASSERT(scene_ != nullptr && T_world_cam_at_ != nullptr);
  period_ns_ = std::max<std::int64_t>(1, std::llround(1e9 / options_.fps));
  options_.queue_depth = std::max<std::size_t>(1, options_.queue_depth);

  const int n = options_.supersampling;
  const std::size_t per_pixel = static_cast<std::size_t>(n * n);
  rays_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * per_pixel * 3,
               std::numeric_limits<float>::quiet_NaN());
  camera_.visit([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    syntheticParallelRows(height_, options_.threads, [] { return false; }, [&](int v0, int v1) {
      for (int v = v0; v < v1; ++v) {
        for (int u = 0; u < width_; ++u) {
          float* ray = &rays_[(static_cast<std::size_t>(v) * width_ + u) * per_pixel * 3];
          for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i, ray += 3) {
              const typename Model::Vec2 px(u + (i + 0.5) / n - 0.5, v + (j + 0.5) / n - 0.5);
              typename Model::Vec3 d;
              if (!model.unproject(px, d)) continue;
              d.normalize();
              ray[0] = static_cast<float>(d.x());
              ray[1] = static_cast<float>(d.y());
              ray[2] = static_cast<float>(d.z());
            }
          }
        }
      }
    });
  });
}

SyntheticCamera::~SyntheticCamera() { stop(); }

bool SyntheticCamera::render(std::int64_t t_ns, std::vector<std::uint8_t>& rgb,
                             const std::atomic<bool>* cancel) const {
  const SceneView view = scene_->view(t_ns, T_world_cam_at_(t_ns));
  const int n = options_.supersampling;
  const std::size_t per_pixel = static_cast<std::size_t>(n * n);
  const float scale = 1.0F / static_cast<float>(per_pixel);
  rgb.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3, 0);
  const auto stop = [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); };
  syntheticParallelRows(height_, options_.threads, stop, [&](int v0, int v1) {
    SceneHit hit;
    for (int v = v0; v < v1; ++v) {
      const float* ray = &rays_[static_cast<std::size_t>(v) * width_ * per_pixel * 3];
      std::uint8_t* out = &rgb[static_cast<std::size_t>(v) * width_ * 3];
      for (int u = 0; u < width_; ++u, out += 3) {
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        for (std::size_t s = 0; s < per_pixel; ++s, ray += 3) {
          if (std::isnan(ray[0])) continue;  // outside the model: black
          if (view.intersect(Eigen::Vector3d(ray[0], ray[1], ray[2]), &hit)) sum += hit.rgb;
        }
        for (int c = 0; c < 3; ++c)
          out[c] = static_cast<std::uint8_t>(std::clamp(std::lround(sum[c] * scale), 0L, 255L));
      }
    }
    rows_rendered_.fetch_add(static_cast<std::uint64_t>(v1 - v0), std::memory_order_relaxed);
  });
  return !stop();
}

CameraFrame SyntheticCamera::renderAt(std::int64_t t_ns) const {
  auto pixels = std::make_shared<std::vector<std::uint8_t>>();
  render(t_ns, *pixels, nullptr);
  return frameOf(t_ns, std::move(pixels));
}

CameraFrame SyntheticCamera::frameOf(std::int64_t capture_ns,
                                     std::shared_ptr<std::vector<std::uint8_t>> pixels) const {
  CameraFrame frame;
  frame.capture_ns = capture_ns;
  frame.exposure_us = options_.exposure_us;
  frame.format = PixelFormat::kRgb8;
  frame.width = width_;
  frame.height = height_;
  frame.stride_bytes = 3 * width_;
  frame.pixels = std::move(pixels);
  frame.timestamp_from_hardware = true;  // exact: the tick the frame was rendered at
  return frame;
}

bool SyntheticCamera::start(std::string* /*error*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (running_) return true;
  if (thread_.joinable()) thread_.join();  // a previous run that stop() is finishing
  stop_requested_.store(false);
  running_ = true;
  thread_ = std::thread([this] { run(); });
  return true;
}

void SyntheticCamera::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_.store(true);
    running_ = false;
    queue_.clear();
  }
  wake_.notify_all();
  ready_.notify_all();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

std::int64_t SyntheticCamera::deliveryDelayNs() const {
  return static_cast<std::int64_t>(options_.exposure_us) * 500 + options_.transfer_ns;
}

void SyntheticCamera::run() {
  const std::int64_t phase = options_.phase_ns;
  const std::int64_t delay = deliveryDelayNs();
  // The first tick at or after now.
  std::int64_t k = -syntheticFloorDiv(phase - clock_.nowNs(), period_ns_);
  while (!stop_requested_.load()) {
    const std::int64_t due = phase + k * period_ns_ + delay;  // exposed, read out, transferred
    {
      std::unique_lock<std::mutex> lock(mutex_);
      for (;;) {
        if (stop_requested_.load()) return;
        const std::int64_t remaining_ns = due - clock_.nowNs();
        if (remaining_ns <= 0) break;
        // Poll at ≤ 1 ms: a simulated clock moves without telling anyone.
        wake_.wait_for(lock, std::chrono::nanoseconds(std::min<std::int64_t>(remaining_ns, 1'000'000)));
      }
    }
    const std::int64_t latest = syntheticFloorDiv(clock_.nowNs() - delay - phase, period_ns_);
    const std::int64_t wanted = std::max(k, latest);
    const std::int64_t chosen = options_.trigger ? options_.trigger->tickFor(k, wanted) : wanted;
    if (chosen > k) {
      skipped_ticks_.fetch_add(static_cast<std::uint64_t>(chosen - k), std::memory_order_relaxed);
      k = chosen;
    }
    const std::int64_t capture_ns = phase + k * period_ns_;
    auto pixels = std::make_shared<std::vector<std::uint8_t>>();
    if (!render(capture_ns, *pixels, &stop_requested_)) return;
    CameraFrame frame = frameOf(capture_ns, std::move(pixels));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_requested_.load()) return;
      frame.sequence = next_sequence_++;
      queue_.push_back(std::move(frame));
      while (queue_.size() > options_.queue_depth) {
        queue_.pop_front();
        ++stats_.lost;
      }
    }
    ready_.notify_all();
    ++k;
  }
}

std::optional<CameraFrame> SyntheticCamera::nextFrame(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait_for(lock, timeout, [this] { return !running_ || !queue_.empty(); });
  if (!running_ || queue_.empty()) return std::nullopt;
  CameraFrame frame = std::move(queue_.front());
  queue_.pop_front();
  ++stats_.frames;
  return frame;
}

std::uint64_t SyntheticCamera::framesRendered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return next_sequence_;
}

CameraStats SyntheticCamera::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace telesphere::robot::cameras
