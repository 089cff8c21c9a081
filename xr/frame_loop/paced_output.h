// SPDX-License-Identifier: MIT
/// @brief Outputs without a headset runtime (offscreen and desktop modes): display frames paced
///        by the steady clock at rate_hz (an overrun skips refreshes, never bursts), the head
///        pose from a function of the display time (the clock can be a simulated one, FrameClock), the eyes ipd apart on the head's x axis, each
///        eye drawn into an offscreen target of its own. What "shown" means is the subclass's:
///        OffscreenOutput waits for the GL (glFinish); the desktop window presents both eyes.
#pragma once

#include <functional>
#include <memory>

#include "shaders/offscreen_target.h"
#include "xr/frame_loop/frame_clock.h"
#include "xr/frame_loop/operator_loop.h"

namespace telesphere::xr::frame_loop {

struct PacedOutputOptions {
  double rate_hz = 90.0;   ///< display rate, (0, 1000]
  double ipd = 0.064;      ///< m
  int eye_width = 1440;    ///< px per eye (the paper's Vive Pro Eye)
  int eye_height = 1600;
  render::Fov fov{-0.87, 0.87, 0.90, -0.90};  ///< rad, about 100° × 104°
};

class PacedOutput : public OperatorOutput {
 public:
  /// The head pose predicted for a display time, in seconds since the first frame began.
  using HeadAt = std::function<Eigen::Isometry3d(double display_s)>;

  /// Makes the eye targets (needs a current GL context); check complete(). `clock` (outlives
  /// this; null: the steady clock) paces the frames and stamps them.
  PacedOutput(const PacedOutputOptions& options, HeadAt head, FrameClock* clock = nullptr);

  /// Sleeps until the next frame is due (frame() does it when this was not called): call it
  /// before reading input that the next frame's head pose should reflect.
  void waitUntilDue();
  bool frame(const DrawEye& draw, Shown* shown, std::string* error) final;

  bool complete() const { return left_.complete() && right_.complete(); }
  const gl::OffscreenTarget& left() const { return left_; }
  const gl::OffscreenTarget& right() const { return right_; }
  /// Eye `eye` in the head frame: ∓ipd/2 along x.
  const Eigen::Isometry3d& T_hmd_eye(int eye) const { return T_hmd_eye_[std::size_t(eye)]; }
  const PacedOutputOptions& options() const { return options_; }
  /// The display period, and when the next frame starts (its head pose is sampled for one
  /// period later); meaningful once the first frame began.
  std::int64_t periodNs() const { return period_ns_; }
  std::int64_t nextStartNs() const { return next_start_ns_; }

 protected:
  /// Shows the drawn eyes; false with the reason.
  virtual bool present(std::string* error) = 0;

 private:
  PacedOutputOptions options_;
  HeadAt head_;
  SteadyFrameClock steady_;
  FrameClock* clock_;
  gl::OffscreenTarget left_, right_;
  std::array<Eigen::Isometry3d, 2> T_hmd_eye_;
  std::int64_t period_ns_;
  std::optional<std::int64_t> first_start_ns_;
  std::int64_t next_start_ns_ = 0;
  bool due_ = true;  ///< next_start_ has been waited for (or none yet)
  std::uint64_t index_ = 0;
};

/// Offscreen: a frame is shown when the GL has finished it.
class OffscreenOutput final : public PacedOutput {
 public:
  using PacedOutput::PacedOutput;

 protected:
  bool present(std::string*) override;
};

}  // namespace telesphere::xr::frame_loop
