// SPDX-License-Identifier: MIT
/// @brief A timestamped joint measurement of the 6-axis head arm, and the joint vector type.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace telesphere::robot::arm {

/// Joint angles (or rates) of the six xArm joints, J1..J6, in rad (rad/s).
using JointVector = Eigen::Matrix<double, 6, 1>;

/// What the arm reports about itself with every state.
enum class ArmStatus {
  kOk,            ///< following targets
  kStopped,       ///< stopped by a fault or an emergency stop; targets are refused until cleared
  kDisconnected,  ///< the link to the arm is down; no states arrive, targets are refused
};

/// One joint measurement: `q` measured at `t_ns` (steady clock of the robot computer).
struct JointState {
  std::int64_t t_ns = 0;
  JointVector q = JointVector::Zero();
  ArmStatus status = ArmStatus::kOk;
};

}  // namespace telesphere::robot::arm
