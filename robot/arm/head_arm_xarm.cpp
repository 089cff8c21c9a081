// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm's HeadArm calls: start, update (silence watch), sendTarget (through the
///        JointTargetGuard), pollState, status, stop, clearStop, stats.
#include "robot/arm/head_arm_xarm.h"
#include "robot/arm/head_arm_xarm_impl.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace telesphere::robot::arm {

XArmHeadArm::XArmHeadArm(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

XArmHeadArm::~XArmHeadArm() {
  if (impl_->connection) {
    // Leave the arm holding still: stop streaming (the controller holds the last set-point).
    impl_->send(Register::kSetState, std::vector<std::uint8_t>{std::uint8_t(xarm::ControllerState::kStopped)}, false);
    impl_->disconnect();
  }
}

std::unique_ptr<XArmHeadArm> XArmHeadArm::start(const XArmOptions& options, const clock::Clock& clock, std::string* error,
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

}  // namespace telesphere::robot::arm
