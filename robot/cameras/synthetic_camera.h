// SPDX-License-Identifier: MIT
/// @brief A CameraSource that renders a SyntheticScene through a calibrated camera model
///        (DESIGN.md §4): the ground truth of the accuracy tests, the image source of the
///        calibration tests and the demo's default camera.
///
/// Each frame is exposed around a tick t_k = phase_ns + k·period_ns of the host clock (its
/// capture_ns, the middle of the exposure) and rendered at the camera pose T_world_cam(t_k) and
/// the scene at t_k. Like a real camera it is delivered only after the exposure has ended and
/// the image has been read out and transferred: at t_k + exposure/2 + transfer_ns (the paper's
/// cameras: 8 ms exposure, about 10 ms over USB). Motion blur is not rendered.
/// Rendering: the unit rays of all n×n sub-samples of every pixel (sub-sample (i, j) of pixel
/// (u, v) at (u + (i + ½)/n − ½, v + (j + ½)/n − ½), pixel centres at integers) are unprojected
/// through the model once, at construction; sub-samples outside the model's valid region count
/// as black, so the rim is anti-aliased like calib::renderTarget. Per frame the rays only meet
/// the scene (in the camera frame); rows are shared by `threads` threads. Memory for the rays:
/// width·height·n²·12 bytes (4K: 100 MB at n = 1, 400 MB at n = 2).
///
/// Two ways to use it: renderAt(t_ns) renders one frame directly (tests, benchmarks, offline
/// images); start() runs a thread that waits for each tick on the clock (a SimClock makes frames
/// step deterministically: set the clock to a tick, take the frame) and queues frames for
/// nextFrame(). When rendering falls behind, ticks are skipped (the next frame is exposed at the
/// latest tick reached, counted by skippedTicks(); with a shared SyntheticTrigger, at the tick a
/// partner camera chose, so that a stereo pair keeps exposing the same ticks); sequence numbers
/// stay gap-free, and only frames dropped from a full queue (the consumer too slow) count as lost.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "calib/generic_camera.h"
#include "robot/cameras/camera_source.h"
#include "robot/clock/clock.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/cameras/synthetic_trigger.h"

namespace telesphere::robot::cameras {

struct SyntheticCameraOptions {
  std::string name = "synthetic";
  double fps = 30.0;                ///< ticks per second of the host clock (> 0)
  std::int64_t phase_ns = 0;        ///< tick k is at phase_ns + k·period (two cameras with equal
                                    ///< fps and phase act as if hardware-triggered together)
  std::uint32_t exposure_us = 5000; ///< reported in the frames; half of it delays delivery
  std::int64_t transfer_ns = 0;     ///< readout and transfer after the exposure ends
  int supersampling = 1;            ///< n: n×n rays per pixel, 1…8 (the speed/accuracy knob)
  int threads = 2;                  ///< rendering threads per frame (≥ 1)
  std::size_t queue_depth = 4;      ///< frames waiting for nextFrame(); the oldest is dropped
  /// Shared by the two cameras of a stereo pair (same fps and phase): when rendering falls
  /// behind, a camera renders the tick its partner chose rather than skipping past it (see
  /// synthetic_trigger.h). Null: the camera skips on its own.
  std::shared_ptr<SyntheticTrigger> trigger;
};

class SyntheticCamera final : public CameraSource {
 public:
  /// A camera with intrinsics `camera` on a width×height sensor (px, 1…32768), seeing `scene`
  /// from the pose T_world_cam_at(t_ns) (optical frame; called from the render thread), paced by
  /// `clock`, which must outlive the camera.
  SyntheticCamera(const calib::GenericCamera& camera, int width, int height,
                  std::shared_ptr<const SyntheticScene> scene, PoseAtTime T_world_cam_at,
                  const clock::Clock& clock, SyntheticCameraOptions options = {});
  ~SyntheticCamera() override;
  SyntheticCamera(const SyntheticCamera&) = delete;
  SyntheticCamera& operator=(const SyntheticCamera&) = delete;

  /// The RGB8 frame exposed at t_ns (capture_ns = t_ns, sequence 0); thread-safe, no clock.
  CameraFrame renderAt(std::int64_t t_ns) const;

  std::string name() const override { return options_.name; }
  bool start(std::string* error) override;
  /// Stops the thread (an unfinished frame is abandoned within a few rows) and wakes
  /// nextFrame(); idempotent. start() may run again afterwards (sequence numbers continue).
  void stop() override;
  std::optional<CameraFrame> nextFrame(std::chrono::milliseconds timeout) override;
  CameraStats stats() const override;

  std::int64_t periodNs() const { return period_ns_; }
  /// From a frame's capture_ns (mid-exposure) to its delivery: exposure/2 + transfer_ns.
  std::int64_t deliveryDelayNs() const;
  /// Ticks passed over because rendering (or the clock) ran ahead of the frame rate.
  std::uint64_t skippedTicks() const { return skipped_ticks_.load(std::memory_order_relaxed); }
  /// Frames rendered by the thread since construction (queued, delivered or lost).
  std::uint64_t framesRendered() const;
  /// Image rows rendered since construction, of whole and abandoned frames (renderAt's too).
  std::uint64_t rowsRendered() const { return rows_rendered_.load(std::memory_order_relaxed); }
  int width() const { return width_; }
  int height() const { return height_; }
  const calib::GenericCamera& camera() const { return camera_; }

 private:
  /// Renders into `rgb`; false when `cancel` was raised before it finished.
  bool render(std::int64_t t_ns, std::vector<std::uint8_t>& rgb, const std::atomic<bool>* cancel) const;
  void run();
  /// The frame for pixels rendered at capture_ns (sequence set by the caller).
  CameraFrame frameOf(std::int64_t capture_ns, std::shared_ptr<std::vector<std::uint8_t>> pixels) const;

  calib::GenericCamera camera_;
  int width_, height_;
  std::shared_ptr<const SyntheticScene> scene_;
  PoseAtTime T_world_cam_at_;
  const clock::Clock& clock_;
  SyntheticCameraOptions options_;
  std::int64_t period_ns_;
  std::vector<float> rays_;  ///< 3 floats per sub-sample ray, NaN where the model has no ray

  mutable std::mutex mutex_;
  std::condition_variable wake_;  ///< the render thread: stop requested
  std::condition_variable ready_; ///< nextFrame(): a frame queued or stopped
  std::deque<CameraFrame> queue_;
  CameraStats stats_;
  bool running_ = false;
  std::atomic<bool> stop_requested_{false};
  mutable std::atomic<std::uint64_t> rows_rendered_{0};
  std::atomic<std::uint64_t> skipped_ticks_{0};
  std::uint64_t next_sequence_ = 0;
  std::thread thread_;
};

}  // namespace telesphere::robot::cameras
