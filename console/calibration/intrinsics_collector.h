// SPDX-License-Identifier: MIT
/// @brief The kept stereo samples of an intrinsic calibration and their coverage (issue #15),
///        shared by the wizard page and the headless procedure. A sample is offered with the
///        still taken just before it at the same head pose; it is kept when in each camera that
///        sees the target the board is still, and in at least one camera it has enough corners
///        and differs enough from every kept view (calib/sample_gates.h). Coverage per camera
///        through the current camera models (calib/view_coverage.h); joint views (both cameras
///        with enough corners, what T_cam_l_cam_r needs) are counted.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "calib/generic_camera.h"
#include "calib/intrinsic_calibration.h"
#include "calib/sample_gates.h"
#include "calib/view_coverage.h"
#include "console/calibration/stereo_sample.h"

namespace telesphere::console::calibration {

struct SampleVerdict {
  bool keep = false;
  std::string reason;  ///< "kept", or each camera's gate with its number
  /// A camera's board moved since the still before (or there was none): another still at the
  /// same pose may pass.
  bool moving = false;
};

class IntrinsicsCollector {
 public:
  IntrinsicsCollector(const std::array<calib::GenericCamera, 2>& models, int width, int height,
                      const calib::SampleGateOptions& gates = {}, const calib::CoverageOptions& coverage = {});

  /// What the gates say of `sample` (against `previous`, the still before it at the same pose;
  /// null: none) and the kept samples, keeping nothing.
  SampleVerdict judge(const StereoSample& sample, const StereoSample* previous) const;
  /// Judges `sample` and keeps it if it passes.
  SampleVerdict offer(const StereoSample& sample, const StereoSample* previous);
  /// Keeps `sample` (judged before).
  void add(const StereoSample& sample);
  void remove(std::size_t index);
  /// New camera models (after a solve): coverage is recomputed through them.
  void setModels(const std::array<calib::GenericCamera, 2>& models);

  const std::vector<StereoSample>& samples() const { return samples_; }
  const calib::ViewCoverage& coverage(int camera) const { return coverage_[std::size_t(camera)]; }
  int jointViews() const;  ///< samples in which both cameras have ≥ min_corners
  int width() const { return width_; }
  int height() const { return height_; }
  /// A board tag's angular size from the cameras (its size over the board's distance, deg), once
  /// the procedure has found the board; 0 before. The done rule's readable bins depend on it.
  double tagAngleDeg() const { return tag_angle_deg_; }
  void setTagAngleDeg(double deg) { tag_angle_deg_ = deg; }

  /// The solver's input: both cameras' views, aligned (an unusable view is empty).
  std::vector<calib::CameraViews> cameraViews(const std::string& model) const;

 private:
  void rebuildCoverage();

  std::array<calib::GenericCamera, 2> models_;
  int width_, height_;
  calib::SampleGateOptions gates_;
  calib::CoverageOptions coverage_options_;
  std::vector<calib::ViewCoverage> coverage_;
  std::vector<StereoSample> samples_;
  double tag_angle_deg_ = 0.0;
};

}  // namespace telesphere::console::calibration
