// SPDX-License-Identifier: MIT
#include "robot/arm/head_arm_xarm.h"
#include "robot/arm/joint_target_guard.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <limits>
#include <map>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "robot/clock/device_clock_mapping.h"
#include "robot/arm/xarm/tcp_socket.h"
#include "robot/arm/xarm/xarm_codes.h"
#include "robot/arm/xarm/xarm_protocol.h"
#include "robot/arm/xarm/xarm_report.h"
#include <cstdio>
#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot {

using xarm::Frame;
using xarm::Register;
using namespace std::chrono_literals;

namespace {

constexpr std::size_t kMaxQueuedStates = 1000;
constexpr auto kPoll = 20ms;  ///< receive threads wake this often to see whether they should end
constexpr std::int64_t kErrorPollWhileStoppedNs = 250'000'000;  ///< error codes read while stopped on request

std::string ms(std::int64_t ns) { return std::to_string(ns / 1'000'000) + " ms"; }

std::array<double, 6> toArray(const JointVector& q) { return {q[0], q[1], q[2], q[3], q[4], q[5]}; }

JointVector toJoints(const std::array<double, 7>& q) {
  JointVector out;
  for (int i = 0; i < 6; ++i) out[i] = q[std::size_t(i)];
  return out;
}

}  // namespace

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
  Impl(const XArmOptions& o, const Clock& c) : options(o), clock(c) {}
  ~Impl() { disconnect(); }  // the receive threads end before the members they use

  XArmOptions options;
  const Clock& clock;
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
  DeviceClockMapping report_clock{DeviceClockMappingOptions{1000, 500.0, 15'000'000, 10}};
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

  bool connect(std::string* error) {
    auto c = std::make_unique<XArmConnection>();
    const std::string hint = " (is the controller powered, and is this computer on its network? robot/arm/xarm/README.md)";
    auto command = xarm::TcpSocket::connect(options.address, options.command_port, options.connect_timeout, error);
    if (!command) {
      *error = "cannot reach the xArm controller's command port " + *error + hint;
      return false;
    }
    auto report = xarm::TcpSocket::connect(options.address, options.report_port, options.connect_timeout, error);
    if (!report) {
      *error = "cannot reach the xArm controller's report port " + *error + hint;
      return false;
    }
    c->command = std::move(*command);
    c->report = std::move(*report);
    {
      std::lock_guard lock(mutex);
      waiting.clear();
      servo_in_flight.clear();
      protocol = xarm::kPrivateProtocol;  // until the version says which the firmware speaks
      report_clock.reset();
      report_index = 0;
      report_jitter_ms.clear();
      last_report_ns = 0;
      last_report.reset();
      fault_status = ArmStatus::kOk;
      fault.clear();
    }
    XArmConnection* raw = c.get();
    c->command_thread = std::thread([this, raw] { receiveReplies(*raw); });
    c->report_thread = std::thread([this, raw] { receiveReports(*raw); });
    connection = std::move(c);
    return true;
  }

  void disconnect() {
    if (connection) connection->close();
    connection.reset();
  }

  /// Records the first fault (a disconnection replaces a stop: it explains more); wakes waiters.
  void failLocked(ArmStatus status, const std::string& why) {
    if (fault_status == ArmStatus::kOk || (status == ArmStatus::kDisconnected && fault_status != status)) {
      fault_status = status;
      fault = why;
    }
    streaming = false;
    changed.notify_all();
  }

  void receiveReplies(XArmConnection& c) {
    xarm::FrameReader reader;
    std::vector<std::uint8_t> buffer(2048);
    while (!c.closing) {
      std::size_t n = 0;
      std::string error;
      const auto got = c.command.receive(buffer, kPoll, &n, &error);
      if (got == xarm::TcpSocket::Received::kTimeout) continue;
      if (got != xarm::TcpSocket::Received::kData) {
        std::lock_guard lock(mutex);
        if (!c.closing)
          failLocked(ArmStatus::kDisconnected, got == xarm::TcpSocket::Received::kClosed
                                                   ? "the controller closed the command connection (" + c.command.peer() + ")"
                                                   : error);
        return;
      }
      reader.feed(std::span<const std::uint8_t>(buffer.data(), n));
      while (auto frame = reader.next()) handleReply(*frame);
      if (reader.failed()) {
        std::lock_guard lock(mutex);
        failLocked(ArmStatus::kDisconnected, "malformed reply from the controller: " + reader.error());
        return;
      }
    }
  }

  void handleReply(const Frame& frame) {
    std::lock_guard lock(mutex);
    if (frame.protocol != protocol) {  // a controller answers with its request's identifier
      failLocked(ArmStatus::kDisconnected, "the controller answered with protocol id " + std::to_string(frame.protocol) +
                                               " to requests with " + std::to_string(protocol));
      return;
    }
    ++stats.replies;
    if (auto it = waiting.find(frame.transaction); it != waiting.end()) {
      it->second = frame;
      changed.notify_all();
    }
    const auto in_flight = std::find_if(servo_in_flight.begin(), servo_in_flight.end(),
                                        [&](const auto& p) { return p.first == frame.transaction; });
    if (in_flight != servo_in_flight.end()) servo_in_flight.erase(servo_in_flight.begin(), in_flight + 1);
    if (frame.reg == std::uint8_t(Register::kGetErrorWarning) && frame.replyParams().size() >= 2) {
      controller_error = frame.replyParams()[0];
      controller_warning = frame.replyParams()[1];
      // Any reading of the codes while stopped by the controller says why (ours or another's); a
      // fault of the controller's own that came after our stop replaces "stopped on request".
      if (controller_error != 0 && fault_status == ArmStatus::kStopped &&
          (fault.rfind("the controller", 0) == 0 || fault == kStoppedOnRequest))
        fault = "controller error " + xarm::controllerErrorText(controller_error);
    }
    if ((frame.status() & xarm::kStatusError) && streaming) {
      failLocked(ArmStatus::kStopped, "the controller reports an error (reading its code)");
      need_error_query = true;
    }
  }

  void receiveReports(XArmConnection& c) {
    xarm::ReportReader reader;
    std::vector<std::uint8_t> buffer(4096);
    while (!c.closing) {
      std::size_t n = 0;
      std::string error;
      const auto got = c.report.receive(buffer, kPoll, &n, &error);
      if (got == xarm::TcpSocket::Received::kTimeout) continue;
      if (got != xarm::TcpSocket::Received::kData) {
        std::lock_guard lock(mutex);
        if (!c.closing)
          failLocked(ArmStatus::kDisconnected, got == xarm::TcpSocket::Received::kClosed
                                                   ? "the controller closed the report connection (" + c.report.peer() + ")"
                                                   : error);
        return;
      }
      const std::int64_t arrival_ns = clock.nowNs();
      reader.feed(std::span<const std::uint8_t>(buffer.data(), n));
      while (auto report = reader.next()) handleReport(*report, arrival_ns);
      if (reader.failed()) {
        std::lock_guard lock(mutex);
        failLocked(ArmStatus::kDisconnected, "malformed report from the controller: " + reader.error());
        return;
      }
    }
  }

  void handleReport(const xarm::RealtimeReport& r, std::int64_t arrival_ns) {
    std::lock_guard lock(mutex);
    const std::int64_t index_ns = std::int64_t(report_index++) * options.report_period_ns;
    report_clock.add(index_ns, arrival_ns);
    JointState s;
    // Strictly increasing even when the envelope drops (a faster arrival than any before).
    s.t_ns = std::max(report_clock.toHostNs(index_ns) - link_delay_ns, last_stamp_ns + 1);
    last_stamp_ns = s.t_ns;

    s.q = toJoints(r.q);
    s.status = fault_status;
    states.push_back(s);
    while (states.size() > kMaxQueuedStates) states.pop_front();
    if (last_report_ns != 0) {
      report_jitter_ms.push_back(std::abs(double(arrival_ns - last_report_ns - options.report_period_ns)) * 1e-6);
      if (report_jitter_ms.size() > 1000) report_jitter_ms.pop_front();
    }
    last_report_ns = arrival_ns;
    last_report = r;
    ++stats.reports;
    stats.report_drift_ppm = report_clock.driftPpm();
    if (streaming) {
      if (r.state == std::uint8_t(xarm::ControllerState::kStopped)) {
        failLocked(ArmStatus::kStopped, "the controller stopped the arm (reading its error code)");
        need_error_query = true;
      } else if (r.mode != std::uint8_t(xarm::ControllerMode::kServo)) {
        failLocked(ArmStatus::kStopped, "the controller left servo mode (now " + xarm::modeName(r.mode) + ")");
      }
    }
    changed.notify_all();
  }

  // ---- requests ---------------------------------------------------------------------------------

  /// Sends without waiting; the transaction, or nothing (fault recorded) when the send failed.
  std::optional<std::uint16_t> send(Register reg, std::span<const std::uint8_t> params, bool wait_for_reply) {
    std::uint16_t transaction = 0;
    std::uint16_t identifier = xarm::kPrivateProtocol;
    {
      std::lock_guard lock(mutex);
      if (!connection) return std::nullopt;
      identifier = protocol;
      transaction = next_transaction;
      next_transaction = static_cast<std::uint16_t>(next_transaction % 65535 + 1);
      if (wait_for_reply) waiting[transaction] = std::nullopt;
      if (reg == Register::kMoveServoJoint) servo_in_flight.emplace_back(transaction, clock.nowNs());
    }
    const auto bytes = xarm::encodeRequest(transaction, reg, params, identifier);
    std::string error;
    bool sent = false;
    {
      std::lock_guard send_lock(connection->send_mutex);
      sent = connection->command.sendAll(bytes, 100ms, &error);
    }
    if (!sent) {
      std::lock_guard lock(mutex);
      waiting.erase(transaction);
      failLocked(ArmStatus::kDisconnected, "cannot send to the controller: " + error);
      return std::nullopt;
    }
    return transaction;
  }

  /// Sends and waits for the reply; nothing with the reason on timeout, disconnection or a reply
  /// to another register.
  std::optional<Frame> request(Register reg, std::span<const std::uint8_t> params, std::string* error,
                               std::chrono::milliseconds timeout = std::chrono::milliseconds(0)) {
    if (timeout.count() == 0) timeout = options.reply_timeout;
    const auto transaction = send(reg, params, true);
    std::unique_lock lock(mutex);
    if (!transaction) {
      *error = xarm::registerName(std::uint8_t(reg)) + ": " + fault;
      return std::nullopt;
    }
    const bool answered = changed.wait_for(lock, timeout, [&] {
      return waiting[*transaction].has_value() || fault_status == ArmStatus::kDisconnected;
    });
    std::optional<Frame> reply = std::move(waiting[*transaction]);
    waiting.erase(*transaction);
    if (!reply) {
      *error = xarm::registerName(std::uint8_t(reg)) + ": " +
               (answered ? fault : "no reply within " + std::to_string(timeout.count()) + " ms");
      return std::nullopt;
    }
    if (reply->reg != std::uint8_t(reg)) {
      *error = xarm::registerName(std::uint8_t(reg)) + ": the reply was for " + xarm::registerName(reply->reg);
      return std::nullopt;
    }
    return reply;
  }

  /// A request whose reply must not say "failed" (bit 3); its error and warning bits are for the caller.
  bool command(Register reg, std::vector<std::uint8_t> params, std::string* error) {
    const auto reply = request(reg, params, error);
    if (!reply) return false;
    if (reply->status() & xarm::kStatusFailed) {
      *error = xarm::registerName(std::uint8_t(reg)) + ": the controller did not carry it out";
      return false;
    }
    return true;
  }

  /// Waits until a report that arrived after this call satisfies `ok` (or the connection fails /
  /// the time is up). Older reports may predate the commands just sent.
  bool waitForReport(const std::function<bool(const xarm::RealtimeReport&)>& ok, std::chrono::milliseconds timeout,
                     const std::string& what, std::string* error) {
    std::unique_lock lock(mutex);
    const std::uint64_t after = report_index;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    const auto satisfied = [&] {
      return (report_index > after && last_report && ok(*last_report)) || fault_status == ArmStatus::kDisconnected;
    };
    bool done = false;
    while (!(done = satisfied()) && std::chrono::steady_clock::now() < deadline) {
      // Waited a keepalive without a request: one that needs no answer keeps the connection in use.
      if (!changed.wait_until(lock, std::min(deadline, std::chrono::steady_clock::now() + options.keepalive), satisfied)) {
        lock.unlock();
        send(Register::kGetState, {}, false);
        lock.lock();
      }
    }
    if (done && fault_status != ArmStatus::kDisconnected) return true;
    *error = fault_status == ArmStatus::kDisconnected
                 ? fault
                 : what + ": not reached within " + std::to_string(timeout.count()) + " ms" +
                       (last_report ? " (controller: " + xarm::stateName(last_report->state) + ", " +
                                          xarm::modeName(last_report->mode) + " mode)"
                                    : std::string(" (no report yet)"));
    return false;
  }

  /// Reads the error and warning codes; clears them when `clear` (and says why it cannot: an
  /// emergency stop still pressed, an error that comes back).
  bool checkErrors(bool clear, std::string* error) {
    auto reply = request(Register::kGetErrorWarning, {}, error);
    if (!reply || reply->replyParams().size() < 2) {
      if (reply) *error = "get error/warning (15): short reply";
      return false;
    }
    int code = reply->replyParams()[0];
    const int warning = reply->replyParams()[1];
    if (code == 0 && (warning == 0 || !clear)) return true;
    if (!clear) {
      *error = "the controller reports " + xarm::controllerErrorText(code) +
               (xarm::isEmergencyStop(code) ? ": release the emergency stop, then clear it" : ": check the arm and its surroundings, then clear it") +
               " (the console's \"clear fault\", --arm-clear-errors, or UFACTORY Studio)";
      return false;
    }
    if (!command(Register::kCleanError, {}, error) || !command(Register::kCleanWarning, {}, error)) return false;
    reply = request(Register::kGetErrorWarning, {}, error);
    if (!reply || reply->replyParams().size() < 2) {
      if (reply) *error = "get error/warning (15): short reply";
      return false;
    }
    code = reply->replyParams()[0];
    if (code != 0) {
      *error = "the controller reports " + xarm::controllerErrorText(code) +
               (xarm::isEmergencyStop(code) ? ": release the emergency stop first" : " again after clearing it");
      return false;
    }
    std::lock_guard lock(mutex);
    controller_error = 0;
    controller_warning = reply->replyParams()[1];
    return true;
  }

  /// Motors on, servo mode, state 0, and the reports show servo mode moving or ready.
  bool enterServoMode(std::string* error) {
    const std::uint8_t servo = std::uint8_t(xarm::ControllerMode::kServo);
    if (!command(Register::kMotionEnable, {8, 1}, error) || !command(Register::kSetMode, {servo}, error) ||
        !command(Register::kSetState, {0}, error))
      return false;
    if (!waitForReport(
            [&](const xarm::RealtimeReport& r) {
              return r.mode == servo && (r.state == std::uint8_t(xarm::ControllerState::kMoving) ||
                                         r.state == std::uint8_t(xarm::ControllerState::kReady));
            },
            1000ms, "servo mode", error))
      return false;
    std::lock_guard lock(mutex);
    streaming = true;
    fault_status = ArmStatus::kOk;
    fault.clear();
    guard.startFrom(toJoints(last_report->q), clock.nowNs());  // from where the arm is
    servo_in_flight.clear();
    return true;
  }

  bool moveToNominal(const JointVector& q, const std::function<void(const std::string&)>& progress, std::string* error) {
    if (!kinematics.withinLimits(q)) {
      *error = "the nominal joints are outside the xArm 6's limits";
      return false;
    }
    if (progress) progress("moving to the nominal pose at " + std::to_string(int(std::lround(options.nominal_speed * 180 / M_PI))) + "°/s");
    if (!command(Register::kMotionEnable, {8, 1}, error) ||
        !command(Register::kSetMode, {std::uint8_t(xarm::ControllerMode::kPosition)}, error) ||
        !command(Register::kSetState, {0}, error) ||
        !command(Register::kMoveJoint, xarm::moveJointParams(toArray(q), options.nominal_speed, options.nominal_acceleration),
                 error))
      return false;
    const std::uint8_t stopped = std::uint8_t(xarm::ControllerState::kStopped);
    if (!waitForReport(
            [&](const xarm::RealtimeReport& r) {
              if (r.state == stopped) return true;  // an error or emergency stop ended the move
              if (r.state == std::uint8_t(xarm::ControllerState::kMoving)) return false;
              for (int i = 0; i < 6; ++i)
                if (std::abs(r.q[std::size_t(i)] - q[i]) > 0.01) return false;
              return true;
            },
            options.nominal_timeout, "the nominal pose", error))
      return false;
    std::uint8_t state = 0;
    {
      std::lock_guard lock(mutex);
      state = last_report->state;
    }
    if (state != stopped) return true;
    const auto codes = request(Register::kGetErrorWarning, {}, error);
    *error = "the controller stopped the move to the nominal pose" +
             (codes && codes->replyParams().size() >= 2 && codes->replyParams()[0] != 0
                  ? ": " + xarm::controllerErrorText(codes->replyParams()[0])
                  : std::string(" (stopped from elsewhere)"));
    return false;
  }

  /// One-way link delay: half the fastest of N "get state" round trips.
  bool measureLinkDelay(std::string* error) {
    std::int64_t best = std::numeric_limits<std::int64_t>::max();
    for (int i = 0; i < std::max(1, options.link_delay_samples); ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      if (!request(Register::kGetState, {}, error)) return false;
      best = std::min<std::int64_t>(best, std::chrono::duration_cast<std::chrono::nanoseconds>(
                                              std::chrono::steady_clock::now() - t0).count());
    }
    std::lock_guard lock(mutex);
    link_delay_ns = best / 2;
    stats.link_delay_ms = double(link_delay_ns) * 1e-6;
    return true;
  }

  /// The payload and collision sensitivity as configured, then what the controller reports it
  /// uses (its normal report); false with both values when they differ or cannot be read.
  bool configureHead(const std::function<void(const std::string&)>& progress, std::string* error) {
    const bool configured = options.payload_kg || options.collision_sensitivity;
    if (options.payload_kg) {
      if (progress) progress("payload " + std::to_string(*options.payload_kg) + " kg");
      if (!command(Register::kSetTcpLoad, xarm::tcpLoadParams(*options.payload_kg, options.payload_com_mm), error))
        return false;
    }
    if (options.collision_sensitivity) {
      if (!command(Register::kSetCollisionSensitivity, {std::uint8_t(*options.collision_sensitivity)}, error))
        return false;
    }
    std::string why;
    const auto report = readNormalReport(&why);
    std::lock_guard lock(mutex);
    stats.readback_error = why;
    stats.payload_read = report.has_value();
    if (!report) {
      if (!configured) return true;  // nothing to check; the health view says it is unknown
      *error = "cannot read back the payload and collision sensitivity (normal report port " +
               std::to_string(options.normal_report_port) + "): " + why;
      return false;
    }
    stats.payload_kg = report->payload_kg;
    stats.payload_com_mm = report->payload_com_mm;
    stats.collision_sensitivity = report->collision_sensitivity;
    char text[320];
    if (options.payload_kg &&
        (std::abs(report->payload_kg - *options.payload_kg) > 0.005 ||
         std::abs(report->payload_com_mm[0] - options.payload_com_mm[0]) > 0.5 ||
         std::abs(report->payload_com_mm[1] - options.payload_com_mm[1]) > 0.5 ||
         std::abs(report->payload_com_mm[2] - options.payload_com_mm[2]) > 0.5)) {
      std::snprintf(text, sizeof text,
                    "the controller reports a payload of %.3f kg at (%.1f, %.1f, %.1f) mm, configured %.3f kg at "
                    "(%.1f, %.1f, %.1f) mm: it did not take the head's payload (check it in UFACTORY Studio)",
                    report->payload_kg, report->payload_com_mm[0], report->payload_com_mm[1], report->payload_com_mm[2],
                    *options.payload_kg, options.payload_com_mm[0], options.payload_com_mm[1], options.payload_com_mm[2]);
      *error = text;
      return false;
    }
    if (options.collision_sensitivity && report->collision_sensitivity != *options.collision_sensitivity) {
      std::snprintf(text, sizeof text, "the controller reports collision sensitivity %d, configured %d",
                    int(report->collision_sensitivity), *options.collision_sensitivity);
      *error = text;
      return false;
    }
    return true;
  }

  /// One report from the normal report port (a connection of its own, closed after it).
  std::optional<xarm::NormalReport> readNormalReport(std::string* error) {
    auto socket = xarm::TcpSocket::connect(options.address, options.normal_report_port, options.connect_timeout, error);
    if (!socket) return std::nullopt;
    xarm::NormalReportReader reader;
    std::vector<std::uint8_t> buffer(1024);
    const auto deadline = std::chrono::steady_clock::now() + 1500ms;  // the port reports at 5 Hz
    while (std::chrono::steady_clock::now() < deadline) {
      std::size_t n = 0;
      const auto got = socket->receive(buffer, kPoll, &n, error);
      if (got == xarm::TcpSocket::Received::kTimeout) continue;
      if (got != xarm::TcpSocket::Received::kData) {
        if (got == xarm::TcpSocket::Received::kClosed) *error = "the controller closed the normal report connection";
        return std::nullopt;
      }
      reader.feed(std::span<const std::uint8_t>(buffer.data(), n));
      if (auto report = reader.next()) return report;
      if (reader.failed()) {
        *error = "malformed normal report: " + reader.error();
        return std::nullopt;
      }
    }
    *error = "no normal report within 1.5 s";
    return std::nullopt;
  }

  /// Connect → version (and the identifier it speaks) → serial → link delay → errors → payload and
  /// sensitivity → first report (start-up and reconnect share it).
  bool prepare(bool clear_errors, const std::function<void(const std::string&)>& progress, std::string* error) {
    if (progress) progress("connecting to the xArm controller at " + options.address);
    if (!connect(error)) return false;
    auto version = request(Register::kGetVersion, {}, error);
    if (!version) return false;
    const auto text = version->replyParams();
    std::string firmware(text.begin(), std::find(text.begin(), text.end(), std::uint8_t(0)));
    const auto parsed = xarm::parseFirmwareVersion(text);
    {
      std::lock_guard lock(mutex);
      stats.firmware = firmware;
      protocol = parsed ? parsed->protocol() : xarm::kPrivateProtocol;
      stats.protocol = protocol;
    }
    if (progress)
      progress("controller firmware: " + firmware + " (protocol identifier " + std::to_string(stats.protocol) + ")");
    std::string serial_error;
    if (const auto sn = request(Register::kGetRobotSn, {}, &serial_error); sn && !(sn->status() & xarm::kStatusFailed)) {
      std::lock_guard lock(mutex);
      stats.serial = xarm::armSerialOfReply(sn->replyParams());
    }
    if (!measureLinkDelay(error) || !checkErrors(clear_errors, error) || !configureHead(progress, error)) return false;
    return waitForReport([](const xarm::RealtimeReport&) { return true; }, 1000ms,
                         "a report on port " + std::to_string(options.report_port), error);
  }
};

XArmHeadArm::XArmHeadArm(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

XArmHeadArm::~XArmHeadArm() {
  if (impl_->connection) {
    // Leave the arm holding still: stop streaming (the controller holds the last set-point).
    impl_->send(Register::kSetState, std::vector<std::uint8_t>{std::uint8_t(xarm::ControllerState::kStopped)}, false);
    impl_->disconnect();
  }
}

std::unique_ptr<XArmHeadArm> XArmHeadArm::start(const XArmOptions& options, const Clock& clock, std::string* error,
                                                 const std::function<void(const std::string&)>& progress) {
  if (options.address.empty()) {
    *error = "no controller address (--arm-address IP)";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>(options, clock);
  if (!impl->prepare(options.clear_errors, progress, error)) return nullptr;
  if (options.nominal_q && !impl->moveToNominal(*options.nominal_q, progress, error)) return nullptr;
  if (progress) progress("servo mode: streaming joint targets");
  if (!impl->enterServoMode(error)) return nullptr;
  return std::unique_ptr<XArmHeadArm>(new XArmHeadArm(std::move(impl)));
}

void XArmHeadArm::update() {
  Impl& m = *impl_;
  bool query = false;
  {
    std::lock_guard lock(m.mutex);
    if (m.streaming) {
      const std::int64_t now = m.clock.nowNs();
      const std::int64_t report_limit = m.options.report_silence_limit.count() * 1'000'000;
      const std::int64_t reply_limit = m.options.reply_silence_limit.count() * 1'000'000;
      if (m.last_report_ns != 0 && now - m.last_report_ns > report_limit)
        m.failLocked(ArmStatus::kDisconnected, "no joint report for " + ms(now - m.last_report_ns) + " (limit " +
                                                   ms(report_limit) + ")");
      else if (!m.servo_in_flight.empty() && now - m.servo_in_flight.front().second > reply_limit)
        m.failLocked(ArmStatus::kDisconnected, "the controller did not answer a servo command for " +
                                                   ms(now - m.servo_in_flight.front().second) + " (limit " +
                                                   ms(reply_limit) + ")");
    }
    // Stopped on request, the controller is still watched: an emergency stop pressed now must not
    // read "stopped on request" (its reports say "stopped" either way; only the code tells).
    const std::int64_t now = m.clock.nowNs();
    if (!m.streaming && m.fault_status == ArmStatus::kStopped && m.fault == kStoppedOnRequest &&
        now - m.last_error_poll_ns >= kErrorPollWhileStoppedNs) {
      m.need_error_query = true;
      m.last_error_poll_ns = now;
    }
    query = std::exchange(m.need_error_query, false) && m.fault_status != ArmStatus::kDisconnected;
  }
  if (query) m.send(Register::kGetErrorWarning, {}, false);  // the reply names the error (handleReply)
}

bool XArmHeadArm::sendTarget(const JointVector& q_target) {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.mutex);
    if (!m.streaming) return false;
    switch (m.guard.check(q_target, m.clock.nowNs())) {
      case JointTargetGuard::Verdict::kAccepted:
        break;
      case JointTargetGuard::Verdict::kOutsideLimits:
        ++m.stats.refused_limits;
        return false;
      case JointTargetGuard::Verdict::kJump:
        ++m.stats.refused_jumps;
        return false;
      case JointTargetGuard::Verdict::kJumpFault:
        ++m.stats.refused_jumps;
        m.failLocked(ArmStatus::kStopped, m.guard.fault());
        return false;
    }
    ++m.stats.targets_sent;
  }
  return m.send(Register::kMoveServoJoint, xarm::servoJointParams(toArray(q_target)), false).has_value();
}

std::optional<JointState> XArmHeadArm::pollState() {
  std::lock_guard lock(impl_->mutex);
  if (impl_->states.empty()) return std::nullopt;
  JointState s = impl_->states.front();
  impl_->states.pop_front();
  return s;
}

ArmStatus XArmHeadArm::status() const {
  std::lock_guard lock(impl_->mutex);
  if (impl_->fault_status != ArmStatus::kOk) return impl_->fault_status;
  return impl_->streaming ? ArmStatus::kOk : ArmStatus::kStopped;
}

std::string XArmHeadArm::faultText() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->fault;
}

void XArmHeadArm::stop() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.mutex);
    if (!m.streaming) return;
    m.failLocked(ArmStatus::kStopped, kStoppedOnRequest);
  }
  m.send(Register::kSetState, std::vector<std::uint8_t>{std::uint8_t(xarm::ControllerState::kStopped)}, false);
}

bool XArmHeadArm::clearStop() {
  Impl& m = *impl_;
  ArmStatus status;
  {
    std::lock_guard lock(m.mutex);
    status = m.fault_status;
    if (status == ArmStatus::kOk && m.streaming) return true;
  }
  std::string error;
  bool ok = false;
  if (status == ArmStatus::kDisconnected) {
    m.disconnect();
    ok = m.prepare(true, {}, &error) && m.enterServoMode(&error);
    if (ok) {
      std::lock_guard lock(m.mutex);
      ++m.stats.reconnects;
    }
  } else {
    ok = m.checkErrors(true, &error) && m.enterServoMode(&error);
  }
  if (!ok) {
    std::lock_guard lock(m.mutex);
    // Still (or again) unreachable: disconnected; reachable but not ready (an error, an emergency stop): stopped.
    if (!m.connection) m.fault_status = ArmStatus::kDisconnected;
    else if (m.fault_status != ArmStatus::kDisconnected) m.fault_status = ArmStatus::kStopped;
    m.fault = "cannot resume: " + error;
    m.streaming = false;
  }
  return ok;
}

XArmHeadArm::Stats XArmHeadArm::stats() const {
  std::lock_guard lock(impl_->mutex);
  Stats s = impl_->stats;
  if (!impl_->report_jitter_ms.empty()) {
    std::vector<double> sorted(impl_->report_jitter_ms.begin(), impl_->report_jitter_ms.end());
    const std::size_t k = std::min(sorted.size() - 1, std::size_t(std::llround(0.99 * double(sorted.size() - 1))));
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(k), sorted.end());
    s.report_jitter_ms_p99 = sorted[k];
  }
  return s;
}

}  // namespace telesphere::robot
