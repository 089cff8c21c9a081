// SPDX-License-Identifier: MIT
/// @brief A simulated xArm controller that speaks the real protocol on loopback (or any address):
///        the command port (frames, transaction ids, the registers XArmHeadArm uses, the reply
///        status bits) and the real-time report port (87-byte reports pushed every 10 ms), backed
///        by robot::SimulatedArm's dynamics (top speed, acceleration, command latency, encoder
///        noise, joint limits). It keeps the controller's state machine: motors enabled or not,
///        mode (position / servo), state (moving, ready, stopped, mode changed), error and warning
///        codes; position-mode joint moves at the requested speed; servo targets executed at once.
///
///        Like a controller of firmware 2.3: it echoes each request's protocol identifier (2, or
///        3 "with heartbeat"), ignores the old identifier-1 heartbeat frames, and drops an
///        identifier-3 client that sent nothing for id3_silence_limit (UFACTORY does not document
///        that limit; its own clients send a request after 30 s of silence, so it is longer); a
///        serial number and version string of the real form; the payload (register 36) and
///        collision sensitivity (37) it is set to, reported on the normal report port (30001,
///        5 Hz, 145 bytes) as a real one reports them.
///
///        Faults to inject, as a real controller shows them: an emergency stop (C1, held until
///        released), a collision stop (C31), an out-of-limit servo target (C23, refused and the arm
///        stopped), the report stream or the replies falling silent, every connection dropped, and
///        raw bytes (malformed or truncated data) sent on either port.
///
///        Used by the driver's tests, `telesphere-bench head --arm xarm-sim` and
///        `telesphere-xarm-sim` (a lab can rehearse `telesphere-robot --arm xarm` against it).
/// One concept: the simulated controller (about 530 lines) — both ports serve one state machine
/// (motors, mode, state, error and warning codes) that a split would have to share.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "robot/arm/head_arm_sim.h"

namespace telesphere::xarm {

struct ControllerSimulatorOptions {
  std::string address = "127.0.0.1";
  int command_port = 0;  ///< 0: a free port (commandPort() says which)
  int report_port = 0;
  robot::arm::SimulatedArmConfig arm;  ///< dynamics; state_period_ns is the report period (10 ms)
  int normal_report_port = 0;  ///< 30001 on a controller
  /// Register 1 (≤ 39 characters of 40): "axis,type,armSN,boxSN,vX.Y.Z" as UFACTORY's firmware writes it.
  std::string firmware = "6,6,XI1202,AC1302,v2.3.0";
  std::string robot_sn = "XI120204201B02", box_sn = "AC130202B02L02";  ///< register 2
  std::chrono::milliseconds id3_silence_limit{40000};
  double payload_kg = 0.0;               ///< as it was last set (before: the factory's none)
  int collision_sensitivity = 3;
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
  /// Register 36 is acknowledged but the controller keeps its old payload (a fault to show
  /// that the driver checks what the controller reports).
  void setPayloadWritesIgnored(bool ignored);
  int normalReportPort() const;

  struct Snapshot {
    std::uint8_t state = 0, mode = 0;
    int error = 0, warning = 0;
    bool enabled = false;
    robot::arm::JointVector q_true = robot::arm::JointVector::Zero();  ///< rad, noise-free
    robot::arm::JointVector set_point = robot::arm::JointVector::Zero();
    std::uint64_t servo_commands = 0;   ///< servo targets taken
    std::uint64_t reports_sent = 0;
    int command_clients = 0, report_clients = 0, normal_report_clients = 0;
    std::uint16_t last_protocol = 0;   ///< of the last request
    std::uint64_t heartbeats = 0;      ///< identifier-1 frames seen
    double payload_kg = 0;
    std::array<double, 3> payload_com_mm{};
    int collision_sensitivity = 0;
  };
  Snapshot snapshot() const;

 private:
  struct Impl;
  explicit ControllerSimulator(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::xarm
