// SPDX-License-Identifier: MIT
/// @brief The kept hand-eye samples and their solve (issue #15, paper eqs. 1–3), shared by the
///        wizard page and the headless procedure:
///   - a sample is kept when the head's or the wrist's rotation differs by at least
///     min_rotation_deg from every kept sample's (near-duplicates add nothing but weight);
///   - the rotation-diversity meter: how far the head's and the wrist's rotation axes spread
///     (calib::checkHandEyeIdentifiability), against the bound the solve needs;
///   - solve(): the three transforms with standard deviations from `auto_solve_from` samples
///     on (the wizard solves again on every new sample); per-sample residuals, outliers marked
///     (RMS above outlier_factor × the median and above outlier_floor_px), removable;
///   - the done rule, with numbers.
/// Degenerate sets (rotations about one axis) are refused by the solve with the reason, never
/// written as a result.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calib/hand_eye_calibration.h"
#include "calib/system_calibration.h"
#include "console/calibration/hand_eye_sample.h"
#include "console/calibration/intrinsics_done_rule.h"

namespace telesphere::console::calibration {

struct HandEyeDoneRule {
  int min_samples = 15;
  double min_axis_spread_deg = 10.0;      ///< head and wrist (calib::HandEyeOptions' bound)
  double max_translation_std_mm = 2.0;    ///< |σ_t| of T_flange_cam_l and of T_robot_mount
  double max_rotation_std_deg = 0.2;      ///< |σ_r| of the same two
  double max_rms_px = 1.0;                ///< both cameras
  /// "15 samples · head and wrist axes spread ≥ 10° · |σ_t| ≤ 2 mm, |σ_r| ≤ 0.2° for T_flange_cam_l
  /// and T_robot_mount · RMS ≤ 1 px".
  std::string describe() const;
};

struct HandEyeCollectorOptions {
  double min_rotation_deg = 3.0;  ///< from every kept sample, head or wrist
  int auto_solve_from = 5;
  double outlier_factor = 3.0;
  double outlier_floor_px = 1.0;
  HandEyeDoneRule rule;
};

/// `cameras` with the three transforms of `result` (the rest of `cameras` unchanged).
calib::SystemCalibration withHandEye(calib::SystemCalibration cameras, const calib::HandEyeResult& result);

class HandEyeCollector {
 public:
  /// `cameras`: the intrinsics and T_cam_l_cam_r the solve holds fixed (its hand-eye transforms,
  /// if any, are what the result replaces).
  HandEyeCollector(calib::SystemCalibration cameras, WristMarker marker, HandEyeCollectorOptions options = {});

  /// Keeps `sample` unless it is too close to a kept one; false with the reason.
  bool offer(const HandEyeStillSample& sample, std::string* reason);
  void remove(std::size_t index);
  /// Removes the samples marked as outliers by the last solve; how many.
  int removeOutliers();

  /// The diversity meter over the kept samples.
  calib::HandEyeIdentifiability diversity() const;

  /// Solves from the kept samples (needs auto_solve_from); false with the reason, which the
  /// result then stays cleared with. `progress`: the solver's lines.
  bool solve(std::string* error, const std::function<void(const std::string&)>& progress = {});
  const std::optional<calib::HandEyeResult>& result() const { return result_; }
  /// Per kept sample: RMS px of the last solve (NaN where it was not used or none ran) and
  /// whether it is an outlier.
  std::vector<double> sampleRmsPx() const;
  std::vector<bool> outliers() const;
  /// The RMS above which a sample is an outlier (NaN before a solve over ≥ 3 samples).
  double outlierBoundPx() const;

  /// The done rule on the kept samples and the last result.
  DoneCheck check() const;
  /// `cameras` with the result's transforms (nothing without a result).
  std::optional<calib::SystemCalibration> calibration() const;

  const std::vector<HandEyeStillSample>& samples() const { return samples_; }
  const calib::SystemCalibration& cameras() const { return cameras_; }
  const WristMarker& marker() const { return marker_; }
  const HandEyeCollectorOptions& options() const { return options_; }

 private:
  calib::HandEyeOptions solverOptions() const;

  calib::SystemCalibration cameras_;
  WristMarker marker_;
  HandEyeCollectorOptions options_;
  std::vector<HandEyeStillSample> samples_;
  std::optional<calib::HandEyeResult> result_;
  std::vector<double> rms_px_;  ///< per sample, of result_
};

}  // namespace telesphere::console::calibration
