// SPDX-License-Identifier: MIT
/// @brief The automatic intrinsic and stereo calibration on the live robot (issue #15; the
///        headless `telesphere-console calibrate intrinsics --auto` and the wizard's "auto" run
///        it in a worker thread). With a fixed Aprilgrid in view of the head at the start:
///
///   1. hold the head where it is; a still; find the board (its centre from the corners'
///      bearings through the planning model: --initial's, or a generic fisheye guess);
///   2. visit the inner targets of the view plan (intrinsics_view_plan.h): at each pose hold,
///      wait until settled, take stills until two in a row agree (the stillness gate), offer
///      the second one to the collector (the gates); a pose the arm refuses is asked for again
///      from the start pose, then the target's fallback poses (other rolls, head positions);
///   3. a quick solve of the left camera refines the planning model (and the board's distance,
///      which says in which rim rings its tags can be read); the outer targets (edges, corners:
///      the rim) are planned through it and visited while the done rule's collection part is
///      unmet; while it is unmet afterwards, the poses that gave nothing (not settled, no still,
///      still moving) once more, then a fill ring of targets with other rolls;
///   4. the full stereo solve with standard deviations; the done rule's solve part; when only
///      that part is unmet, one more ring of views (other rolls) and the solve again;
///   5. the head is taken back to its start pose and released (also on failure and cancel).
/// Every step is logged; the figures (poses refused/unsettled, stills, gate rejections, time
/// from the first sample to the result) come back with the result.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "calib/aprilgrid.h"
#include "calib/intrinsic_calibration.h"
#include "calib/system_calibration.h"
#include "console/calibration/calibration_robot.h"
#include "console/calibration/intrinsics_collector.h"
#include "console/calibration/intrinsics_done_rule.h"
#include "console/calibration/intrinsics_view_plan.h"

namespace telesphere::console::calibration {

/// Where a run stands (for a progress bar); reported after every pose and at the solve.
struct IntrinsicsProgress {
  std::string stage;  ///< "inner views", "rim views", "retrying", "fill views", "solving", "more views", "done"
  int samples = 0;            ///< kept so far
  int poses_visited = 0;
  int poses_planned = 0;
  const StereoSample* last_kept = nullptr;  ///< the sample kept at this pose (valid during the call)
};

struct IntrinsicsProcedureOptions {
  calib::AprilGrid grid;
  std::string model = "ds";
  /// The calibration the robot starts with, if known: plans the head poses (scaled to the
  /// stills' resolution); the result keeps its hand-eye transforms.
  std::optional<calib::SystemCalibration> initial;
  calib::DetectionOptions detection;
  /// The gates; 12 corners are enough (the solver's own minimum): near the image's corners
  /// only part of the board is in view.
  calib::SampleGateOptions gates = [] {
    calib::SampleGateOptions g;
    g.min_corners = 12;
    return g;
  }();
  calib::CoverageOptions coverage;
  IntrinsicsDoneRule rule;
  SettleOptions settle;
  int max_stills_per_pose = 6;
  int max_views = 60;  ///< stop collecting here even if coverage is unmet
  /// When set, every still is written here as still-NNN-left.png / -right.png (full resolution,
  /// for telesphere-calib or kalibr later) and stills.csv says where each was taken and its verdict.
  std::string stills_dir;
  std::function<void(const std::string&)> log;  ///< one line per step (any thread)
  std::function<void(const IntrinsicsProgress&)> progress;  ///< (the worker's thread)
  const std::atomic<bool>* cancel = nullptr;
};

struct IntrinsicsOutcome {
  bool done = false;    ///< a result that meets the done rule
  std::string error;    ///< why not (empty when done)
  std::optional<calib::IntrinsicResult> result;
  /// The result with the initial calibration's hand-eye transforms (when given), ready to save.
  std::optional<calib::SystemCalibration> calibration;
  std::optional<IntrinsicsCollector> collector;
  DoneCheck collection, solve;
  std::string rule_text;
  /// Targets (a planned pose with its fallbacks, counted once): planned, visited, refused (the arm
  /// took none of its poses, from where it stood or from the start pose), and held but not settled.
  int poses_planned = 0, poses_visited = 0, poses_refused = 0, poses_unsettled = 0;
  /// Refused targets reached with another pose (PlannedView::fallback); not counted as planned.
  int fallback_poses_held = 0;
  /// Poses refused from where the arm stood and held once it was back at the start pose.
  int poses_held_from_start = 0;
  int stills = 0, samples_rejected = 0;
  double first_sample_to_result_s = 0;  ///< wall time
  double total_s = 0;
  /// The head was taken back to where the run found it before it was released (every run that
  /// moved it does this, done, not done, failed or cancelled); why not when it could not be.
  bool head_returned = false;
  std::string head_return_error;
};

/// Runs the procedure against the robot behind `robot`. It starts where the head is (the
/// supervisor put the board in view from there) and, whatever the outcome, ends there: the head
/// is taken back to its start pose (bounded by options.settle's timeout) before it is released.
IntrinsicsOutcome runIntrinsicsAuto(CalibrationRobot& robot, const IntrinsicsProcedureOptions& options);

/// A board tag's angular size (deg) seen from `distance_m` away.
double tagAngleDeg(const calib::AprilGrid& grid, double distance_m);

/// `rule` with the tag angle of the board the collector's samples show (collector.tagAngleDeg()),
/// unless the rule sets its own.
IntrinsicsDoneRule ruleInEffect(const IntrinsicsDoneRule& rule, const IntrinsicsCollector& collector);

/// Solves the samples in `collector` (again, e.g. after the user deleted some) and fills in
/// `out`'s result, calibration, done checks and error; the collector ends up in `out`.
void solveCollected(IntrinsicsCollector collector, const IntrinsicsProcedureOptions& options, IntrinsicsOutcome& out);

/// The models a run starts from at width × height: the initial calibration's, scaled, where
/// given; otherwise genericFisheye.
std::array<calib::GenericCamera, 2> startingModels(const IntrinsicsProcedureOptions& options, int width, int height);

/// A generic fisheye guess for `model` at width × height (about 200° across the width) when no
/// calibration is known.
calib::GenericCamera genericFisheye(const std::string& model, int width, int height);

}  // namespace telesphere::console::calibration
