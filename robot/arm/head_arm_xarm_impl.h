// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm's inside, shared by its files (private to robot/arm): the connection and its
///        receive threads (head_arm_xarm_link.cpp), the report stream stamped on our clock
///        (head_arm_xarm_reports.cpp), the start-up steps (head_arm_xarm_startup.cpp) and the HeadArm
///        calls (head_arm_xarm.cpp). One mutex guards the state below; see head_arm_xarm.h.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "robot/arm/head_arm_xarm.h"
#include "robot/arm/joint_target_guard.h"
#include "robot/arm/xarm6_kinematics.h"
#include "robot/arm/xarm/tcp_socket.h"
#include "robot/arm/xarm/xarm_codes.h"
#include "robot/arm/xarm/xarm_protocol.h"
#include "robot/arm/xarm/xarm_report.h"
#include "robot/clock/device_clock_mapping.h"

namespace telesphere::robot::arm {

using xarm::Frame;
using xarm::Register;
using namespace std::chrono_literals;

constexpr std::size_t kMaxQueuedStates = 1000;
constexpr auto kPoll = 20ms;  ///< receive threads wake this often to see whether they should end
constexpr std::int64_t kErrorPollWhileStoppedNs = 250'000'000;  ///< error codes read while stopped on request

inline std::string ms(std::int64_t ns) { return std::to_string(ns / 1'000'000) + " ms"; }

inline std::array<double, 6> toArray(const JointVector& q) { return {q[0], q[1], q[2], q[3], q[4], q[5]}; }

inline JointVector toJoints(const std::array<double, 7>& q) {
  JointVector out;
  for (int i = 0; i < 6; ++i) out[i] = q[std::size_t(i)];
  return out;
}

/// One connection to the controller: its two sockets and the two threads that read them.
struct XArmConnection {
  xarm::TcpSocket command, report;
  std::thread command_thread, report_thread;
  std::atomic<bool> closing{false};
  std::mutex send_mutex;  ///< one writer at a time on the command socket

  ~XArmConnection() { close(); }
  void close() {
    closing = true;
    command.shutdown();
    report.shutdown();
    if (command_thread.joinable()) command_thread.join();
    if (report_thread.joinable()) report_thread.join();
  }
};

struct XArmHeadArm::Impl {
  Impl(const XArmOptions& o, const clock::Clock& c) : options(o), clock(c) {}
  ~Impl() { disconnect(); }  // the receive threads end before the members they use

  XArmOptions options;
  const clock::Clock& clock;
  Xarm6Kinematics kinematics;
  std::unique_ptr<XArmConnection> connection;

  mutable std::mutex mutex;
  std::condition_variable changed;  ///< a reply or report arrived, or the connection failed
  std::map<std::uint16_t, std::optional<Frame>> waiting;  ///< synchronous requests by transaction
  std::uint16_t protocol = xarm::kPrivateProtocol;  ///< the identifier requests carry (the firmware's)
  std::deque<std::pair<std::uint16_t, std::int64_t>> servo_in_flight;  ///< (transaction, sent ns)
  std::uint16_t next_transaction = 1;

  /// Report index × period → our clock. TCP loses nothing, but a controller that falls behind
  /// may skip a report, and then every later report seems a period late against its index: ten
  /// reports in a row more than 1.5 periods late (or one impossibly early) restart the fit on
  /// the arrivals as they are now. A single late arrival (a busy machine) only leaves the envelope.
  clock::DeviceClockMapping report_clock{clock::DeviceClockMappingOptions{1000, 500.0, 15'000'000, 10}};
  std::int64_t last_stamp_ns = 0;  ///< stamps handed out stay strictly increasing
  std::uint64_t report_index = 0;
  std::int64_t last_report_ns = 0;
  std::deque<double> report_jitter_ms;  ///< |arrival interval − period|, the last 1000
  std::optional<xarm::RealtimeReport> last_report;
  std::deque<JointState> states;
  std::int64_t link_delay_ns = 0;

  bool streaming = false;
  ArmStatus fault_status = ArmStatus::kOk;  ///< kOk: no fault
  std::string fault;
  int controller_error = 0, controller_warning = 0;
  bool need_error_query = false;
  std::int64_t last_error_poll_ns = 0;  ///< while stopped on request (update())

  JointTargetGuard guard{{options.max_velocity, options.report_period_ns, options.refused_jumps_for_fault}};
  Stats stats;

  // ---- connection -------------------------------------------------------------------------------

  bool connect(std::string* error);

  void disconnect();

  /// Records the first fault (a disconnection replaces a stop: it explains more); wakes waiters.
  void failLocked(ArmStatus status, const std::string& why);

  void receiveReplies(XArmConnection& c);

  void handleReply(const Frame& frame);

  void receiveReports(XArmConnection& c);

  void handleReport(const xarm::RealtimeReport& r, std::int64_t arrival_ns);

  // ---- requests ---------------------------------------------------------------------------------

  /// Sends without waiting; the transaction, or nothing (fault recorded) when the send failed.
  std::optional<std::uint16_t> send(Register reg, std::span<const std::uint8_t> params, bool wait_for_reply);

  /// Sends and waits for the reply; nothing with the reason on timeout, disconnection or a reply
  /// to another register.
  std::optional<Frame> request(Register reg, std::span<const std::uint8_t> params, std::string* error,
                               std::chrono::milliseconds timeout = std::chrono::milliseconds(0));

  /// A request whose reply must not say "failed" (bit 3); its error and warning bits are for the caller.
  bool command(Register reg, std::vector<std::uint8_t> params, std::string* error);

  /// Waits until a report that arrived after this call satisfies `ok` (or the connection fails /
  /// the time is up). Older reports may predate the commands just sent.
  bool waitForReport(const std::function<bool(const xarm::RealtimeReport&)>& ok, std::chrono::milliseconds timeout,
                     const std::string& what, std::string* error);

  /// Reads the error and warning codes; clears them when `clear` (and says why it cannot: an
  /// emergency stop still pressed, an error that comes back).
  bool checkErrors(bool clear, std::string* error);

  /// Motors on, servo mode, state 0, and the reports show servo mode moving or ready.
  bool enterServoMode(std::string* error);

  bool moveToNominal(const JointVector& q, const std::function<void(const std::string&)>& progress, std::string* error);

  /// One-way link delay: half the fastest of N "get state" round trips.
  bool measureLinkDelay(std::string* error);

  /// The payload and collision sensitivity as configured, then what the controller reports it
  /// uses (its normal report); false with both values when they differ or cannot be read.
  bool configureHead(const std::function<void(const std::string&)>& progress, std::string* error);

  /// One report from the normal report port (a connection of its own, closed after it).
  std::optional<xarm::NormalReport> readNormalReport(std::string* error);

  /// Connect → version (and the identifier it speaks) → serial → link delay → errors → payload and
  /// sensitivity → first report (start-up and reconnect share it).
  bool prepare(bool clear_errors, const std::function<void(const std::string&)>& progress, std::string* error);
};

}  // namespace telesphere::robot::arm
