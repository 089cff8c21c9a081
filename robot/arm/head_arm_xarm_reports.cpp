// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm's report stream: each 100 Hz report becomes a JointState stamped on our clock by the
///        report clock fit (DeviceClockMapping over report index × period, minus the link delay);
///        a controller that stops or leaves servo mode is a fault.
#include "robot/arm/head_arm_xarm_impl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace telesphere::robot::arm {

void XArmHeadArm::Impl::handleReport(const xarm::RealtimeReport& r, std::int64_t arrival_ns) {
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

}  // namespace telesphere::robot::arm
