// SPDX-License-Identifier: MIT
/// @brief The automatic hand-eye calibration on the live robot (issue #15, paper §III-B; the
///        headless `telesphere-console calibrate handeye --auto` and the wizard's hand-eye page
///        run it in a worker thread). With the manipulator's wrist marker in view:
///
///   1. the head runs the predefined sinusoidal pattern about the nominal pose (link
///      CalibrationHeadPose.pattern_amplitude_deg; amplitude 0: it holds where it is) while the
///      manipulator moves (teach mode; in simulation its scripted path);
///   2. stills, one after another: each becomes a sample (marker corners in both cameras, both
///      arms' forward kinematics at the capture time, freshness checked) and is kept unless it
///      is too close to a kept one (hand_eye_collector.h);
///   3. from 5 samples on, a solve after every new sample; outliers are removed and the solve
///      repeated; the done rule is checked;
///   4. until the rule holds, max_samples are kept or the time limit passes; the head is
///      released (also on failure and cancel).
/// The cameras' intrinsics are scaled to the stills' resolution for the solve; the result is
/// written at the calibration's own resolution.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calib/system_calibration.h"
#include "console/calibration/calibration_robot.h"
#include "console/calibration/hand_eye_collector.h"

namespace telesphere::console::calibration {

struct HandEyeProgress {
  int stills = 0;
  bool kept = false;
  std::string verdict;  ///< of the last still: "kept", or why not
  DoneCheck check;      ///< the done rule after it
  const HandEyeCollector* collector = nullptr;  ///< valid during the call (null before a first sample)
};

/// One solve along the way (accuracy against sample count).
struct HandEyeSolveStep {
  int samples = 0;
  double elapsed_s = 0;  ///< since the first sample
  bool ok = false;
  std::string error;
  double rms_px = 0;
  double flange_cam_sigma_t_mm = 0, flange_cam_sigma_r_deg = 0;
  calib::HandEyeResult result;
};

struct HandEyeProcedureOptions {
  calib::SystemCalibration cameras;  ///< intrinsics and T_cam_l_cam_r (needed); hand-eye replaced
  WristMarker marker;
  HandEyeCollectorOptions collector;
  double pattern_amplitude_deg = 20.0;
  int max_samples = 60;
  int max_stills = 400;
  std::chrono::seconds time_limit{900};
  bool remove_outliers = true;
  SettleOptions settle;  ///< the head's return to its start pose at the end
  std::function<void(const std::string&)> log;
  std::function<void(const HandEyeProgress&)> progress;
  const std::atomic<bool>* cancel = nullptr;
};

struct HandEyeOutcome {
  bool done = false;
  std::string error;
  std::optional<HandEyeCollector> collector;
  /// options.cameras (own resolution) with the three transforms; set whenever a solve succeeded.
  std::optional<calib::SystemCalibration> calibration;
  DoneCheck check;
  std::string rule_text;
  int stills = 0, refused = 0, too_close = 0, outliers_removed = 0;
  std::vector<HandEyeSolveStep> history;
  double first_sample_to_result_s = 0;
  double total_s = 0;
  /// The head was taken back to where the run found it before it was released (whatever the
  /// outcome, once the pattern or hold started); why not when it could not be.
  bool head_returned = false;
  std::string head_return_error;
};

/// Runs the procedure against the robot behind `robot`: the head swings along the calibration
/// pattern (or holds still) while the user moves the marker; at the end it is taken back to the
/// pose the run found it at (bounded by options.settle's timeout), then released.
HandEyeOutcome runHandEyeAuto(CalibrationRobot& robot, const HandEyeProcedureOptions& options);

/// After a solve of out.collector (`ok`, or `error`): the done rule's check, done, the
/// calibration (`cameras`, at their own resolution, with the result) and the error. Also for a
/// solve again after the user deleted samples.
void takeSolve(HandEyeOutcome& out, const calib::SystemCalibration& cameras, bool ok, const std::string& error);

/// `cameras` at width × height (intrinsics scaled); nothing with the reason.
std::optional<calib::SystemCalibration> camerasAt(const calib::SystemCalibration& cameras, int width, int height,
                                                  std::string* error);

}  // namespace telesphere::console::calibration
