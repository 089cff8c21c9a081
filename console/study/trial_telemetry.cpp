// SPDX-License-Identifier: MIT
/// @brief Trial telemetry: stored envelopes → head and robot samples → CSV (trial_telemetry.h).
#include "console/study/trial_telemetry.h"

#include <QDateTime>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const char* outcomeName(link::proto::HeadTickOutcome outcome) {
  switch (outcome) {
    case link::proto::HEAD_TICK_SENT: return "sent";
    case link::proto::HEAD_TICK_NOT_INITIALISED: return "not_initialised";
    case link::proto::HEAD_TICK_NO_TARGET: return "no_target";
    case link::proto::HEAD_TICK_REJECTED: return "rejected";
    case link::proto::HEAD_TICK_ARM_REFUSED: return "arm_refused";
    default: return "unknown";
  }
}

std::string csvField(double v) {
  if (!std::isfinite(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

std::optional<std::int64_t> utcNs(const std::string& iso) {
  const QDateTime t = QDateTime::fromString(QString::fromStdString(iso), Qt::ISODateWithMs);
  if (!t.isValid()) return std::nullopt;
  return t.toMSecsSinceEpoch() * 1'000'000;
}

TrialTelemetry decodeTrialTelemetry(const std::vector<TelemetryBatch>& batches, std::int64_t trial_start_utc_ns) {
  TrialTelemetry out;
  for (const TelemetryBatch& batch : batches) {
    ++out.batches;
    link::proto::Envelope envelope;
    if (!envelope.ParseFromString(batch.envelope)) {
      ++out.undecodable_batches;
      continue;
    }
    if (!batch.robot_to_utc_ns) {
      ++out.unsynced_batches;
      continue;
    }
    const auto seconds = [&](std::int64_t robot_ns) {
      return double(robot_ns + *batch.robot_to_utc_ns - trial_start_utc_ns) * 1e-9;
    };
    if (envelope.has_robot_telemetry()) {
      for (const auto& tick : envelope.robot_telemetry().ticks()) {
        RobotSample s;
        s.t_s = seconds(tick.t_ns());
        s.outcome = outcomeName(tick.outcome());
        const auto& c = tick.t_robot_head_command();
        const auto& m = tick.t_robot_head_measured();
        s.cmd_x = c.tx(), s.cmd_y = c.ty(), s.cmd_z = c.tz();
        s.cmd_qw = c.qw(), s.cmd_qx = c.qx(), s.cmd_qy = c.qy(), s.cmd_qz = c.qz();
        s.meas_x = m.tx(), s.meas_y = m.ty(), s.meas_z = m.tz();
        s.meas_qw = m.qw(), s.meas_qx = m.qx(), s.meas_qy = m.qy(), s.meas_qz = m.qz();
        out.robot.push_back(std::move(s));
      }
    } else if (envelope.has_xr_telemetry()) {
      const auto& xr = envelope.xr_telemetry();
      if (!xr.clock_synced()) {
        ++out.unsynced_batches;
        continue;
      }
      const std::int64_t robot_to_xr = xr.robot_to_xr_offset_ns();
      for (const auto& f : xr.frames()) {
        HeadSample s;
        s.t_s = seconds(f.display_ns() - robot_to_xr);
        const auto& p = f.t_vr_hmd();
        s.x = p.tx(), s.y = p.ty(), s.z = p.tz();
        s.qw = p.qw(), s.qx = p.qx(), s.qy = p.qy(), s.qz = p.qz();
        s.head_valid = f.head_valid();
        s.render_ms = f.render_ms();
        s.missed = static_cast<int>(f.missed());
        s.stereo_sequence = f.stereo_sequence();
        // capture is in the robot clock, displayed in the XR clock.
        s.image_latency_ms = f.new_image() && f.stamps().capture_ns() > 0 && f.stamps().displayed_ns() > 0
                                 ? double(f.stamps().displayed_ns() - robot_to_xr - f.stamps().capture_ns()) * 1e-6
                                 : kNaN;
        s.delta_s_m = f.eye_camera_distance_m() >= 0 ? f.eye_camera_distance_m() : kNaN;
        out.head.push_back(s);
      }
    }
  }
  std::stable_sort(out.head.begin(), out.head.end(), [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
  std::stable_sort(out.robot.begin(), out.robot.end(), [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
  return out;
}

std::optional<std::vector<std::string>> writeTrialTelemetryCsv(const TrialTelemetry& telemetry,
                                                               const std::string& path_stem, std::string* error) {
  const std::string head_path = path_stem + "_head.csv", robot_path = path_stem + "_robot.csv";
  std::ofstream head(head_path), robot(robot_path);
  if (!head || !robot) {
    *error = "cannot write " + (head ? robot_path : head_path);
    return std::nullopt;
  }
  head << "t_s,x_m,y_m,z_m,qw,qx,qy,qz,head_valid,render_ms,missed,stereo_sequence,image_latency_ms,delta_s_m\n";
  for (const HeadSample& s : telemetry.head)
    head << csvField(s.t_s) << ',' << csvField(s.x) << ',' << csvField(s.y) << ',' << csvField(s.z) << ',' << csvField(s.qw)
         << ',' << csvField(s.qx) << ',' << csvField(s.qy) << ',' << csvField(s.qz) << ',' << (s.head_valid ? 1 : 0) << ','
         << csvField(s.render_ms) << ',' << s.missed << ',' << s.stereo_sequence << ',' << csvField(s.image_latency_ms)
         << ',' << csvField(s.delta_s_m) << '\n';
  robot << "t_s,outcome,cmd_x_m,cmd_y_m,cmd_z_m,cmd_qw,cmd_qx,cmd_qy,cmd_qz,"
           "meas_x_m,meas_y_m,meas_z_m,meas_qw,meas_qx,meas_qy,meas_qz\n";
  for (const RobotSample& s : telemetry.robot)
    robot << csvField(s.t_s) << ',' << s.outcome << ',' << csvField(s.cmd_x) << ',' << csvField(s.cmd_y) << ','
          << csvField(s.cmd_z) << ',' << csvField(s.cmd_qw) << ',' << csvField(s.cmd_qx) << ',' << csvField(s.cmd_qy) << ','
          << csvField(s.cmd_qz) << ',' << csvField(s.meas_x) << ',' << csvField(s.meas_y) << ',' << csvField(s.meas_z) << ','
          << csvField(s.meas_qw) << ',' << csvField(s.meas_qx) << ',' << csvField(s.meas_qy) << ',' << csvField(s.meas_qz)
          << '\n';
  head.close();
  robot.close();
  if (!head || !robot) {
    *error = "cannot finish writing " + path_stem + "_*.csv";
    return std::nullopt;
  }
  return std::vector<std::string>{head_path, robot_path};
}

}  // namespace telesphere::console::study
