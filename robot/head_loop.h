// SPDX-License-Identifier: MIT
/// @brief The robot side's 100 Hz head loop (DESIGN.md §5) wired to the link: each tick it runs
///        the arm, files its joint states into the joint-state buffer (the video path reads
///        capture-time camera poses from there), feeds the newest head target from the operator
///        to the HeadController, sends the resulting joint target, publishes the robot state and
///        records one telemetry sample (HeadTick) per tick. It also answers the link's control
///        requests for the head: visual mode, sphere radius, filter cut-off, jump threshold, arm
///        stop and clear, and the nominal pose (the headset's one-shot capture, and the console's
///        guided step below).
///
/// Head-target time: a target carries the time the XR app sampled the pose in the robot clock
/// (t_robot_ns, through the XR app's ping offset); the controller's stale / from-future /
/// out-of-order checks run on that stamp, so an uplink that holds targets back shows as stale
/// targets. A target whose sender has no clock offset yet (t_robot_ns = 0, the first pings) is
/// stamped with its arrival here (the tick that first sees it) and counted. A new target is one
/// whose (sender instance, sender stamp) differs from the last one taken; the link server
/// already orders each sender's targets by their own stamps.
///
/// Nominal-pose step (console, DESIGN.md §2; link NominalStepRequest):
///   FOLLOWING --HOLD--> HOLDING (the head moves to T_robot_nom and stays; the operator is asked
///   to look straight ahead) --CAPTURE--> CAPTURED (the newest head pose, if it arrived within
///   max_capture_age_ns, becomes the pending T_vr_nom; still holding) --CONFIRM--> FOLLOWING with
///   the new mapping (the old one kept for undo). UNDO from HOLDING or CAPTURED drops the
///   pending capture and follows with the old mapping; UNDO while FOLLOWING goes back to the
///   mapping before the last confirm (one level).
///
/// Calibration head poses (console wizards, link CalibrationHeadPose): the head goes to the pose
/// and holds there, the operator ignored, until released; not during the nominal-pose step (and
/// no HOLD step while held); poses outside the workspace or out of the arm's reach are refused.
/// With a pattern amplitude the held pose moves every tick along the sinusoidal head pattern of
/// robot/calibration_head_pattern.h (hand-eye sample collection).
///
/// A calibration applied live (HeadLoopConfig::calibration) takes effect at the next tick.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "robot/calibration_in_use.h"
#include "robot/clock.h"
#include "robot/head_arm.h"
#include "robot/head_controller.h"
#include "robot/joint_state_buffer.h"
#include "robot/link/link_server.h"
#include "robot/telemetry_batcher.h"

namespace telesphere::robot {

struct HeadLoopConfig {
  std::int64_t period_ns = HeadArm::kStatePeriodNs;  ///< 100 Hz
  int state_every_ticks = 2;                          ///< robot state at 50 Hz
  int telemetry_every_ticks = 5;                      ///< a telemetry batch every 50 ms
  bool auto_nominal = false;  ///< take the first valid head target as the nominal pose (demo)
  double sphere_radius = 1.0;  ///< m; echoed in the robot state, changed by control requests
  /// A nominal capture needs a head pose that arrived at most this long ago.
  std::int64_t max_capture_age_ns = 250'000'000;
  /// Where the per-tick samples go (with the video path's); null: no telemetry.
  TelemetryBatcher* telemetry = nullptr;
  /// The calibration in use, changed live: a new generation reaches the controller and the
  /// joint-state buffer at the next tick, and the robot state names it. Null: the controller's
  /// geometry stays (generation 0 in the state).
  const CalibrationInUse* calibration = nullptr;
};

/// The link's visual mode ↔ the controller's head mode; nothing for VISUAL_MODE_UNSPECIFIED.

class HeadLoop {
 public:
  HeadLoop(HeadArm& arm, HeadController& controller, JointStateBuffer& buffer,
           link::LinkServer& server, const Clock& clock, const HeadLoopConfig& config = {});

  /// One period's work; tick() is what run() calls every period_ns.
  void tick();

  /// Ticks every period until `stop` becomes true (real time: the clock must be steady).
  void run(const std::atomic<bool>& stop);

  /// A control request for the head (called on the link's thread); other requests (JPEG
  /// settings) are refused with a reason. The reply carries the head's settings.
  link::proto::ControlReply handleControl(const link::proto::ControlRequest& request);

  /// The head's part of the settings (mode, radius, cut-off, jump thresholds).
  void fillSettings(link::proto::RobotSettings* settings) const;
  /// The head's and the arm's part of the health report.
  void fillHealth(link::proto::RobotHealth* health) const;

  std::int64_t ticks() const { return ticks_; }
  std::int64_t targetsSent() const { return targets_sent_; }
  /// Head targets stamped on arrival because their sender had no clock offset yet.
  std::int64_t targetsStampedOnArrival() const { return targets_stamped_on_arrival_; }
  std::optional<JointState> lastState() const;
  link::proto::NominalStep nominalStep() const;
  /// The nominal mapping in force (or pending), as a control reply carries it.
  link::proto::NominalMapping nominalMapping() const;

 private:
  /// The newest head target (robot clock).
  struct ArrivedTarget {
    HmdSample sample;  ///< t_ns: when the XR app sampled it, or its arrival if that is unknown
    std::int64_t sampled_robot_ns = 0;  ///< when the XR app sampled it, robot clock (0: unknown)
    std::int64_t arrival_ns = 0;        ///< the tick that first saw it
  };

  link::proto::NominalMapping nominalMappingLocked() const;
  /// Starts the mapping from `nominal` at the newest joints, keeping the one it replaces for undo.
  bool applyNominalLocked(const HmdSample& nominal);
  bool nominalStepLocked(link::proto::NominalStepRequest step, std::string* error);
  bool calibrationHoldLocked(const link::proto::CalibrationHeadPose& request, std::string* error);
  bool captureNominalLocked(std::string* error);
  std::string faultLocked() const;

  HeadArm& arm_;
  HeadController& controller_;
  JointStateBuffer& buffer_;
  link::LinkServer& server_;
  const Clock& clock_;
  HeadLoopConfig config_;
  Eigen::Isometry3d T_flange_head_;  ///< of the calibration in use (guarded by mutex_)
  std::uint64_t calibration_generation_ = 0;  ///< the one the controller has (0: its own)

  mutable std::mutex mutex_;  ///< everything below (tick vs control thread)
  std::optional<JointState> last_state_;
  std::optional<ArrivedTarget> last_target_;
  std::uint64_t last_target_sender_ = 0;  ///< sender instance of the last target taken
  std::int64_t last_target_t_ns_ = 0;    ///< and its stamp in the sender's clock
  bool pending_nominal_ = false;       ///< the headset's one-shot capture, taken at the next tick
  link::proto::NominalStep step_ = link::proto::NOMINAL_STEP_FOLLOWING;
  std::optional<ArrivedTarget> captured_;           ///< pending while CAPTURED
  std::optional<Eigen::Isometry3d> previous_mapping_;  ///< T_robot_vr before the last confirm
  bool calibration_hold_ = false;  ///< held at a calibration head pose (link CalibrationHeadPose)
  struct HeadPattern {
    Eigen::Isometry3d T_robot_centre;
    double amplitude_deg = 0;
    std::int64_t start_ns = 0;
  };
  std::optional<HeadPattern> pattern_;  ///< while the held pose moves along the pattern
  std::string stop_reason_;  ///< why the arm was stopped on request (empty: not by us)
  double sphere_radius_;
  link::proto::TrialIndicator trial_;  ///< the study's trial indicator, as the console sent it
  std::int64_t trial_received_ns_ = 0;  ///< when it arrived (robot clock)
  std::atomic<std::int64_t> ticks_{0}, targets_sent_{0}, targets_stamped_on_arrival_{0};
};

}  // namespace telesphere::robot
