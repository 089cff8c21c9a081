// SPDX-License-Identifier: MIT
/// @brief ArmRecovery: the supervisor's "clear fault" run on a thread of its own. Clearing an
///        xArm's fault may mean reconnecting (seconds of timeouts when the controller is
///        unreachable); run under the head loop's lock on the link's thread, it froze the robot:
///        no state, no pongs, no head targets. The head loop starts a recovery, calls nothing else
///        on the arm while it runs (HeadArm is not thread-safe), and takes the outcome at a later
///        tick. One concept: the recovery's thread and its outcome.
#pragma once

#include <atomic>
#include <optional>
#include <thread>

#include "robot/arm/head_arm.h"

namespace telesphere::robot::arm {

class ArmRecovery {
 public:
  explicit ArmRecovery(HeadArm& arm) : arm_(arm) {}
  ~ArmRecovery();  ///< waits for a recovery in progress (clearStop is bounded by the arm's timeouts)
  ArmRecovery(const ArmRecovery&) = delete;
  ArmRecovery& operator=(const ArmRecovery&) = delete;

  /// Starts arm.clearStop() on the recovery thread; false (nothing starts) while one runs or its
  /// outcome has not been taken yet.
  bool start();
  /// A recovery runs: the arm belongs to it.
  bool running() const { return running_.load(); }
  /// The outcome of the last recovery (clearStop's return), once, after it finished; nothing while
  /// one runs or when none finished since the last call.
  std::optional<bool> takeOutcome();

 private:
  HeadArm& arm_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> finished_{false};  ///< an outcome waits to be taken
  std::atomic<bool> outcome_{false};
};

}  // namespace telesphere::robot::arm
