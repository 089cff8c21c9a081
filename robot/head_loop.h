// SPDX-License-Identifier: MIT
/// @brief The robot side's 100 Hz head loop (DESIGN.md §5) wired to the link: each tick it runs
///        the arm, files its joint states into the joint-state buffer (the video path reads
///        capture-time camera poses from there), feeds the newest head target from the operator
///        to the HeadController, sends the resulting joint target, and publishes the robot state.
///        It also answers the link's control requests (mode, nominal pose, sphere radius).
///
/// Head-target time: a target is stamped in the operator's clock, so the loop stamps it with
/// its arrival at the robot (the tick that first sees it) for the controller's staleness
/// checks. On loopback and a LAN the uplink adds well under a tick (10 ms) to its age.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "robot/clock.h"
#include "robot/head_arm.h"
#include "robot/head_controller.h"
#include "robot/joint_state_buffer.h"
#include "robot/link/link_server.h"

namespace telesphere::robot {

struct HeadLoopConfig {
  std::int64_t period_ns = HeadArm::kStatePeriodNs;  ///< 100 Hz
  int state_every_ticks = 2;                          ///< robot state at 50 Hz
  bool auto_nominal = false;  ///< take the first valid head target as the nominal pose (demo)
  double sphere_radius = 1.0;  ///< m; echoed in the robot state, changed by control requests
};

/// "full6d", "orientation3d", "fixed" ↔ HeadMode; nothing for other text.
std::optional<HeadMode> headModeFromName(const std::string& name);
const char* headModeName(HeadMode mode);

class HeadLoop {
 public:
  HeadLoop(HeadArm& arm, HeadController& controller, JointStateBuffer& buffer,
           link::LinkServer& server, const Clock& clock, const HeadLoopConfig& config = {});

  /// One period's work; tick() is what run() calls every period_ns.
  void tick();

  /// Ticks every period until `stop` becomes true (real time: the clock must be steady).
  void run(const std::atomic<bool>& stop);

  /// A control request from the link (called on the link's thread).
  link::proto::ControlReply handleControl(const link::proto::ControlRequest& request);

  std::int64_t ticks() const { return ticks_; }
  std::int64_t targetsSent() const { return targets_sent_; }
  std::optional<JointState> lastState() const;

 private:
  HeadArm& arm_;
  HeadController& controller_;
  JointStateBuffer& buffer_;
  link::LinkServer& server_;
  const Clock& clock_;
  HeadLoopConfig config_;

  mutable std::mutex mutex_;  ///< controller_, last_*, pending_nominal_ (tick vs control thread)
  std::optional<JointState> last_state_;
  std::optional<HmdSample> last_sample_;
  std::int64_t last_target_t_ns_ = 0;  ///< operator clock stamp of the last target taken
  bool pending_nominal_ = false;
  double sphere_radius_;
  std::atomic<std::int64_t> ticks_{0}, targets_sent_{0};
};

}  // namespace telesphere::robot
