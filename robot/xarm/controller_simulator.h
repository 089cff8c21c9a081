// SPDX-License-Identifier: MIT
/// @brief A simulated xArm controller that speaks the real protocol on loopback (or any address):
///        the command port (frames, transaction ids, the registers XArmHeadArm uses, the reply
///        status bits) and the real-time report port (87-byte reports pushed every 10 ms), backed
///        by robot::SimulatedArm's dynamics (top speed, acceleration, command latency, encoder
///        noise, joint limits). It keeps the controller's state machine: motors enabled or not,
///        mode (position / servo), state (moving, ready, stopped, mode changed), error and warning
///        codes; position-mode joint moves at the requested speed; servo targets executed at once.
///
///        Faults to inject, as a real controller shows them: an emergency stop (C1, held until
///        released), a collision stop (C31), an out-of-limit servo target (C23, refused and the arm
///        stopped), the report stream or the replies falling silent, every connection dropped, and
///        raw bytes (malformed or truncated data) sent on either port.
///
///        Used by the driver's tests, `telesphere-bench head --arm xarm-sim` and
///        `telesphere-xarm-sim` (a lab can rehearse `telesphere-robot --arm xarm` against it).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "robot/head_arm_sim.h"

namespace telesphere::xarm {

struct ControllerSimulatorOptions {
  std::string address = "127.0.0.1";
  int command_port = 0;  ///< 0: a free port (commandPort() says which)
  int report_port = 0;
  robot::SimulatedArmConfig arm;  ///< dynamics; state_period_ns is the report period (10 ms)
  std::string firmware = "6,6,SIM,SIM,v2.3.0 telesphere-simulator";  ///< ≤ 39 characters (register 1 has 40 bytes)
  std::chrono::microseconds reply_delay{200};  ///< the controller's time to answer a command
};

class ControllerSimulator {
 public:
  /// Listens on both ports and starts the physics (1 kHz) and reports. Null with the reason.
  static std::unique_ptr<ControllerSimulator> start(const ControllerSimulatorOptions& options, std::string* error);
  ~ControllerSimulator();
  ControllerSimulator(const ControllerSimulator&) = delete;
  ControllerSimulator& operator=(const ControllerSimulator&) = delete;

  int commandPort() const;
  int reportPort() const;

  // Faults.
  void pressEmergencyStop();    ///< C1; state stopped, the arm brakes; cannot be cleared until released
  void releaseEmergencyStop();
  void collide();               ///< C31 (collision caused abnormal current); state stopped, the arm brakes
  void setReportsPaused(bool paused);  ///< the report stream stops (connections stay open)
  void setRepliesPaused(bool paused);  ///< commands are read but not answered
  void dropConnections();       ///< closes every client connection (clients may connect again)
  void sendRawReport(std::span<const std::uint8_t> bytes);  ///< to every report client
  void sendRawReply(std::span<const std::uint8_t> bytes);   ///< to every command client

  struct Snapshot {
    std::uint8_t state = 0, mode = 0;
    int error = 0, warning = 0;
    bool enabled = false;
    robot::JointVector q_true = robot::JointVector::Zero();  ///< rad, noise-free
    robot::JointVector set_point = robot::JointVector::Zero();
    std::uint64_t servo_commands = 0;   ///< servo targets taken
    std::uint64_t reports_sent = 0;
    int command_clients = 0, report_clients = 0;
  };
  Snapshot snapshot() const;

 private:
  struct Impl;
  explicit ControllerSimulator(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::xarm
