// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm's connection to the controller: two sockets, the threads that read them, replies
///        matched to their requests, faults recorded once.
#include "robot/arm/head_arm_xarm_impl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace telesphere::robot::arm {

bool XArmHeadArm::Impl::connect(std::string* error) {
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

void XArmHeadArm::Impl::disconnect() {
  if (connection) connection->close();
  connection.reset();
}

void XArmHeadArm::Impl::failLocked(ArmStatus status, const std::string& why) {
  if (fault_status == ArmStatus::kOk || (status == ArmStatus::kDisconnected && fault_status != status)) {
    fault_status = status;
    fault = why;
  }
  streaming = false;
  changed.notify_all();
}

void XArmHeadArm::Impl::receiveReplies(XArmConnection& c) {
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

void XArmHeadArm::Impl::handleReply(const Frame& frame) {
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

void XArmHeadArm::Impl::receiveReports(XArmConnection& c) {
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

std::optional<std::uint16_t> XArmHeadArm::Impl::send(Register reg, std::span<const std::uint8_t> params, bool wait_for_reply) {
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

std::optional<Frame> XArmHeadArm::Impl::request(Register reg, std::span<const std::uint8_t> params, std::string* error,
                             std::chrono::milliseconds timeout) {
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

bool XArmHeadArm::Impl::command(Register reg, std::vector<std::uint8_t> params, std::string* error) {
  const auto reply = request(reg, params, error);
  if (!reply) return false;
  if (reply->status() & xarm::kStatusFailed) {
    *error = xarm::registerName(std::uint8_t(reg)) + ": the controller did not carry it out";
    return false;
  }
  return true;
}

bool XArmHeadArm::Impl::waitForReport(const std::function<bool(const xarm::RealtimeReport&)>& ok, std::chrono::milliseconds timeout,
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

}  // namespace telesphere::robot::arm
