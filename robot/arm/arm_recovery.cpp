// SPDX-License-Identifier: MIT
/// @brief ArmRecovery (see arm_recovery.h).
#include "robot/arm/arm_recovery.h"

namespace telesphere::robot::arm {

ArmRecovery::~ArmRecovery() {
  if (thread_.joinable()) thread_.join();
}

bool ArmRecovery::start() {
  if (running_.load() || finished_.load()) return false;
  if (thread_.joinable()) thread_.join();  // the last one finished and its outcome was taken
  running_ = true;
  thread_ = std::thread([this] {
    outcome_ = arm_.clearStop();
    finished_ = true;
    running_ = false;
  });
  return true;
}

std::optional<bool> ArmRecovery::takeOutcome() {
  if (running_.load() || !finished_.load()) return std::nullopt;
  const bool outcome = outcome_.load();
  finished_ = false;
  return outcome;
}

}  // namespace telesphere::robot::arm
