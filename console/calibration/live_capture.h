// SPDX-License-Identifier: MIT
/// @brief The calibration page's live view and manual capture (issue #15): full-resolution
///        stills one after another, the Aprilgrid detected in both cameras and each still judged
///        by the gates against the one before it, for a board held by hand in front of the head
///        (or a head the supervisor jogs). A still is kept when the gates pass and auto-capture
///        is on, or, with auto-capture off, when the user asked for a capture: then the next
///        still that passes is kept. Synchronous; call step() from a worker thread.
#pragma once

#include <array>
#include <atomic>
#include <optional>
#include <string>

#include "console/calibration/calibration_robot.h"
#include "console/calibration/intrinsics_collector.h"
#include "console/calibration/intrinsics_procedure.h"

namespace telesphere::console::calibration {

/// One still of the live view.
struct LiveStill {
  StereoSample sample;                       ///< corners at full resolution, small thumbnails
  std::array<calib::GrayImage, 2> view;      ///< each camera's image reduced for the live view
  SampleVerdict verdict;                     ///< what the gates say (also when not kept)
  bool kept = false;
  bool capture_pending = false;              ///< a requested capture still waits for a still that passes
  int samples = 0;                           ///< kept so far, this one included
};

class LiveCapture {
 public:
  /// `options` gives the grid, detection, gates, coverage and starting models; `view_width` the
  /// width of each camera's live image.
  LiveCapture(CalibrationRobot& robot, IntrinsicsProcedureOptions options, int view_width = 480);

  void setAutoCapture(bool on) { auto_capture_ = on; }  ///< any thread
  void requestCapture() { capture_requested_ = true; }  ///< any thread

  /// Continues from samples kept earlier (their resolution must match the robot's stills).
  void setCollector(IntrinsicsCollector collector) { collector_ = std::move(collector); }

  /// Takes one still, detects, judges and maybe keeps it; nothing, with the reason, when the
  /// robot gave no still or its resolution differs from the samples kept.
  std::optional<LiveStill> step(std::string* error);

  /// The kept samples (none before the first still unless setCollector was called).
  const std::optional<IntrinsicsCollector>& collector() const { return collector_; }
  std::optional<IntrinsicsCollector> takeCollector() { return std::move(collector_); }
  int stills() const { return stills_; }

 private:
  CalibrationRobot& robot_;
  IntrinsicsProcedureOptions options_;
  int view_width_;
  std::atomic<bool> auto_capture_{true};
  std::atomic<bool> capture_requested_{false};
  std::optional<IntrinsicsCollector> collector_;
  std::optional<StereoSample> previous_;
  int stills_ = 0;
};

}  // namespace telesphere::console::calibration
