// SPDX-License-Identifier: MIT
/// @brief The one operator frame loop (STYLE.md §2, DESIGN.md §2–§4) and the render-target seam
///        under it. An OperatorOutput paces display frames (a steady clock, or the headset
///        runtime's xrWaitFrame), knows where the head and the eyes will be when a frame is shown,
///        owns the eye images and shows them. OperatorLoop::step runs one display frame through an
///        OperatorScene (the OperatorView, or the headset's test scene): the head pose at display time goes to the robot, both eyes are drawn, the
///        frame is shown, display periods skipped since the last frame are counted as missed (from
///        the display times, the same rule for every output), and the view's statistics and
///        telemetry get the frame. Each mode (offscreen, desktop, OpenXR) is an output plus what
///        it does between frames (keys, PNGs, session events).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "shaders/gl_api.h"
#include "xr/render/eye_view.h"

namespace telesphere::xr::frame_loop {

/// What the loop draws: the robot's camera frames (OperatorView) or a scene of its own (the
/// headset's test scene). Frame protocol on the thread whose GL context is current:
/// beginFrame → renderEye(0) → renderEye(1) → endFrame.
class OperatorScene {
 public:
  virtual ~OperatorScene() = default;
  /// Start of a display frame: the head pose predicted for display_ns (steady ns); `valid` false:
  /// the head is not tracked.
  virtual bool beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display_ns, bool valid,
                          std::string* error) = 0;
  /// Eye `eye` (0 left, 1 right) at T_vr_eye into `framebuffer` (fov and size from `view`).
  virtual bool renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view, GLuint framebuffer,
                         std::string* error) = 0;
  /// End of the frame: shown at shown_ns, render_ms the work of both eyes, missed_frames so far.
  virtual void endFrame(std::int64_t shown_ns, double render_ms, std::uint64_t missed_frames) = 0;
  /// The pose the eye at T_vr_eye was rendered with in its camera (T_cam_eye); nothing when the
  /// eye showed no camera image.
  virtual std::optional<Eigen::Isometry3d> T_cam_eye(int eye, const Eigen::Isometry3d& T_vr_eye) const = 0;
};

/// One display frame as its output gives it.
struct DisplayFrame {
  std::uint64_t index = 0;         ///< display frames this output began, from 0
  std::int64_t display_ns = 0;     ///< when it will be shown (predicted), steady clock (the link's), ns
  std::int64_t display_period_ns = 0;  ///< the display's refresh period, ns (0: unknown)
  /// The display time on the output's own clock (the runtime's XrTime for OpenXR; display_ns
  /// otherwise): what skipped refreshes are counted on.
  std::int64_t refresh_ns = 0;
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();  ///< head pose predicted for display_ns
  bool head_valid = true;
  std::array<Eigen::Isometry3d, 2> T_vr_eye{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};
  std::array<render::EyeView, 2> views;    ///< fov and size per eye (T_cam_eye is the renderer's to compute)
};

/// Draws eye `eye` (0 left, 1 right) of `frame` into `framebuffer`; false ends the frame.
using DrawEye = std::function<bool(const DisplayFrame& frame, int eye, GLuint framebuffer)>;

/// The render-target seam.
class OperatorOutput {
 public:
  virtual ~OperatorOutput() = default;

  struct Shown {
    bool began = false;        ///< a display frame was due (false: none, e.g. a session not running)
    bool drawn = false;        ///< both eyes were drawn and the frame shown (or submitted)
    std::int64_t shown_ns = 0;  ///< when it is shown, steady clock ns
    DisplayFrame frame;
  };
  /// Waits for the next display frame, calls draw for each eye it shows, shows them. False when
  /// draw returned false (*error as draw left it) or showing failed (the reason in *error).
  virtual bool frame(const DrawEye& draw, Shown* shown, std::string* error) = 0;
};

struct OperatorLoopStats {
  std::uint64_t frames = 0;         ///< display frames drawn
  std::uint64_t missed_frames = 0;  ///< display periods skipped between drawn frames
  double fps = 0;                   ///< frames drawn per second since the first step
};

class OperatorLoop {
 public:
  /// Both must outlive the loop; the GL context the output draws with must be current.
  OperatorLoop(OperatorScene& scene, OperatorOutput& output) : scene_(scene), output_(output) {}

  /// One display frame. False with the reason when the view or the output failed.
  bool step(std::string* error);
  /// The output's clock starts again (a new headset session): no refreshes are counted as missed
  /// across the restart.
  void outputRestarted() { last_refresh_ns_ = 0; }
  /// What the last step did.
  const OperatorOutput::Shown& last() const { return last_; }
  OperatorLoopStats stats() const;

 private:
  using Clock = std::chrono::steady_clock;
  OperatorScene& scene_;
  OperatorOutput& output_;
  OperatorOutput::Shown last_;
  std::int64_t last_refresh_ns_ = 0;
  OperatorLoopStats stats_;
  std::optional<Clock::time_point> first_step_;
};

/// Display periods skipped between two frames shown `period_ns` apart at best: 0 for consecutive
/// refreshes, n when n refreshes passed without a frame (a gap rounded to whole periods).
std::uint64_t skippedPeriods(std::int64_t previous_display_ns, std::int64_t display_ns, std::int64_t period_ns);

}  // namespace telesphere::xr::frame_loop
