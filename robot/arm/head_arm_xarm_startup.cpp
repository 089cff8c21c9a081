// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm's start-up steps (head_arm_xarm.h): errors, link delay, the head's payload and
///        collision sensitivity read back, the move to the nominal joints, servo mode.
#include "robot/arm/head_arm_xarm_impl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace telesphere::robot::arm {

bool XArmHeadArm::Impl::checkErrors(bool clear, std::string* error) {
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

bool XArmHeadArm::Impl::enterServoMode(std::string* error) {
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

bool XArmHeadArm::Impl::moveToNominal(const JointVector& q, const std::function<void(const std::string&)>& progress, std::string* error) {
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

bool XArmHeadArm::Impl::measureLinkDelay(std::string* error) {
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

bool XArmHeadArm::Impl::configureHead(const std::function<void(const std::string&)>& progress, std::string* error) {
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

std::optional<xarm::NormalReport> XArmHeadArm::Impl::readNormalReport(std::string* error) {
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

bool XArmHeadArm::Impl::prepare(bool clear_errors, const std::function<void(const std::string&)>& progress, std::string* error) {
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

}  // namespace telesphere::robot::arm
