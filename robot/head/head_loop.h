// SPDX-License-Identifier: MIT
/// @brief The robot side's 100 Hz head loop (DESIGN.md §5) wired to the link: each tick it runs
///        the arm, files its joint states into the joint-state buffer (the video path reads
///        capture-time camera poses from there), feeds the newest head target from the operator
///        to the HeadController, sends the resulting joint target, publishes the robot state and
///        records one telemetry sample (HeadTick) per tick. It also answers the link's control
///        requests for the head: visual mode, sphere radius, the session's scene
///        proxy (held for the XR app, which measures the depth behind it), filter cut-off, jump threshold, arm
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
/// robot/head/calibration_head_pattern.h (hand-eye sample collection). A hold is a lease its holder
/// renews (HeadHold in the link schema): not renewed for hold_lease_ns, the tick releases it and
/// says why. The lease clock stands while the robot itself serves a control request (a still
/// may take longer than a lease) and for one lease after, so a holder is never blamed for the
/// robot's own silence (RobotControl marks those with controlStarted/controlFinished).
///
/// A calibration applied live (HeadLoopConfig::calibration) takes effect at the next tick.
///
/// Stops, faults and recovery: while the arm is not ok the controller does not run (the operator's
/// targets are kept, none is sent). "Clear fault" runs the arm's clearStop() on a thread of its own
/// (ArmRecovery: an xArm may reconnect for seconds) and is answered at once with `pending`; ticks go
/// on publishing the state ("clearing the fault …"), the link keeps serving, and nothing else
/// touches the arm until the recovery ends. Once the arm is ok again, the controller resumes from
/// the first joint state measured after that (HeadController::resumeFrom) and approaches where the
/// operator looks now at its slow-approach speed. The fault text names every cause, the arm's own
/// first ("arm stopped: emergency stop; also stopped from the console").
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "robot/arm/arm_recovery.h"
#include "robot/head/calibration_in_use.h"
#include "robot/clock/clock.h"
#include "robot/arm/head_arm.h"
#include "robot/head/head_controller.h"
#include "robot/head/joint_state_buffer.h"
#include "robot/link/depth_proxy.h"
#include "robot/link/link_server.h"
#include "robot/telemetry/telemetry_batcher.h"

namespace telesphere::robot::head {

struct HeadLoopConfig {
  std::int64_t period_ns = arm::HeadArm::kStatePeriodNs;  ///< 100 Hz
  int state_every_ticks = 2;                          ///< robot state at 50 Hz
  int telemetry_every_ticks = 5;                      ///< a telemetry batch every 50 ms
  bool auto_nominal = false;  ///< take the first valid head target as the nominal pose (demo)
  double sphere_radius = 1.0;  ///< m; echoed in the robot state, changed by control requests
  /// The session's scene proxy (#35), echoed in the robot state and changed by control requests;
  /// nothing: each XR app renders with its own (--depth-proxy) until somebody chooses.
  std::optional<link::DepthProxy> depth_proxy;
  /// A nominal capture needs a head pose that arrived at most this long ago.
  std::int64_t max_capture_age_ns = 250'000'000;
  /// Where the per-tick samples go (with the video path's); null: no telemetry.
  telemetry::TelemetryBatcher* telemetry = nullptr;
  /// The calibration in use, changed live: a new generation reaches the controller and the
  /// joint-state buffer at the next tick, and the robot state names it. Null: the controller's
  /// geometry stays (generation 0 in the state).
  const CalibrationInUse* calibration = nullptr;
  /// A calibration hold not renewed for this long is released (its holder went silent).
  std::int64_t hold_lease_ns = 2'000'000'000;
};

/// The link's visual mode ↔ the controller's head mode; nothing for VISUAL_MODE_UNSPECIFIED.

class HeadLoop {
 public:
  HeadLoop(arm::HeadArm& arm, HeadController& controller, JointStateBuffer& buffer,
           link::LinkServer& server, const clock::Clock& clock, const HeadLoopConfig& config = {});

  /// One period's work; tick() is what run() calls every period_ns.
  void tick();

  /// Ticks every period until `stop` becomes true (real time: the clock must be steady).
  void run(const std::atomic<bool>& stop);

  /// A control request for the head (called on the link's thread); other requests (JPEG
  /// settings) are refused with a reason. The reply carries the head's settings.
  link::proto::ControlReply handleControl(const link::proto::ControlRequest& request);

  /// The head's part of the settings (mode, radius, scene proxy, cut-off, jump thresholds).
  void fillSettings(link::proto::RobotSettings* settings) const;
  /// The head's and the arm's part of the health report.
  void fillHealth(link::proto::RobotHealth* health) const;

  /// A control request is being served (RobotControl, around every request): the holds' lease
  /// clock stands meanwhile (see the file comment).
  void controlStarted();
  void controlFinished();

  /// The calibration hold now (lease 0: none).
  link::proto::HeadHold hold() const;

  std::int64_t ticks() const { return ticks_; }
  std::int64_t targetsSent() const { return targets_sent_; }
  /// Head targets stamped on arrival because their sender had no clock offset yet.
  std::int64_t targetsStampedOnArrival() const { return targets_stamped_on_arrival_; }
  std::optional<arm::JointState> lastState() const;
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
  /// Ends the calibration hold (if any) and remembers how, for the next HeadHold.
  void releaseHoldLocked(const std::string& how);
  /// Releases a hold whose holder went silent for a lease.
  void expireHoldLocked(std::int64_t now_ns);
  link::proto::HeadHold holdLocked() const;
  bool captureNominalLocked(std::string* error);
  std::string faultLocked() const;
  /// The arm is ok and no recovery owns it (calls nothing on the arm while one does).
  bool armOkLocked() const;
  /// Takes a finished recovery's outcome; on the ok→not-ok→ok edges, arranges the resume.
  void followArmLocked(std::int64_t now_ns);
  arm::HeadArm& arm_;
  HeadController& controller_;
  JointStateBuffer& buffer_;
  link::LinkServer& server_;
  const clock::Clock& clock_;
  HeadLoopConfig config_;
  Eigen::Isometry3d T_flange_head_;  ///< of the calibration in use (guarded by mutex_)
  std::uint64_t calibration_generation_ = 0;  ///< the one the controller has (0: its own)

  mutable std::mutex mutex_;  ///< everything below (tick vs control thread)
  std::optional<arm::JointState> last_state_;
  std::optional<ArrivedTarget> last_target_;
  std::uint64_t last_target_sender_ = 0;  ///< sender instance of the last target taken
  std::int64_t last_target_t_ns_ = 0;    ///< and its stamp in the sender's clock
  bool pending_nominal_ = false;       ///< the headset's one-shot capture, taken at the next tick
  link::proto::NominalStep step_ = link::proto::NOMINAL_STEP_FOLLOWING;
  std::optional<ArrivedTarget> captured_;           ///< pending while CAPTURED
  std::optional<Eigen::Isometry3d> previous_mapping_;  ///< T_robot_vr before the last confirm
  struct CalibrationHold {
    std::uint64_t lease = 0;
    std::string holder;
    std::int64_t since_ns = 0, renewed_ns = 0;
  };
  std::optional<CalibrationHold> hold_;  ///< held at a calibration head pose (link CalibrationHeadPose)
  std::uint64_t next_lease_ = 1;
  std::string last_release_;             ///< how the last hold ended
  std::atomic<int> controls_in_progress_{0};
  std::atomic<std::int64_t> control_finished_ns_{0};  ///< when the last control request was served
  struct HeadPattern {
    Eigen::Isometry3d T_robot_centre;
    double amplitude_deg = 0;
    std::int64_t start_ns = 0;
  };
  std::optional<HeadPattern> pattern_;  ///< while the held pose moves along the pattern
  bool stopped_by_console_ = false;  ///< the arm was stopped on a control request (until cleared)
  arm::ArmRecovery recovery_;             ///< "clear fault" in progress (the arm is its own meanwhile)
  bool stop_after_recovery_ = false;  ///< a stop request came during a recovery: applied after it
  bool resume_pending_ = false;      ///< the arm was not ok: resume from a fresh joint state
  std::int64_t arm_ok_since_ns_ = 0;  ///< when the arm was seen ok again (0: not yet)
  double sphere_radius_;
  std::optional<link::DepthProxy> depth_proxy_;  ///< the session's scene proxy; nothing: each XR app's own
  link::proto::TrialIndicator trial_;  ///< the study's trial indicator, as the console sent it
  std::int64_t trial_received_ns_ = 0;  ///< when it arrived (robot clock)
  std::atomic<std::int64_t> ticks_{0}, targets_sent_{0}, targets_stamped_on_arrival_{0};
};

}  // namespace telesphere::robot::head
