// SPDX-License-Identifier: MIT
/// @brief One trial's telemetry, decoded for an analyst (paper §IV-B: "plot one trial's head
///        motion"): the operator's head poses and display frames from the XR app, and the robot's
///        head-loop ticks, each at seconds since the trial started (UTC, the trial's start_utc).
///        XR stamps map to the robot clock by the offset the XR app sent with its batch, robot
///        stamps to UTC by the console's offset stored with each batch; batches without either
///        are counted and left out. Written as two tidy CSV files per trial.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "console/study/study_store.h"

namespace telesphere::console::study {

/// One display frame of the XR app.
struct HeadSample {
  double t_s = 0;                      ///< display time, s since the trial started
  double x = 0, y = 0, z = 0;          ///< T_vr_hmd translation, m
  double qw = 1, qx = 0, qy = 0, qz = 0;
  bool head_valid = false;
  double render_ms = 0;
  int missed = 0;                      ///< display periods missed just before
  std::uint64_t stereo_sequence = 0;   ///< camera frame shown
  double image_latency_ms = 0;         ///< capture → displayed on its first display; NaN otherwise
  double delta_s_m = 0;                ///< Δs; NaN when unknown
};

/// One tick of the robot's head loop.
struct RobotSample {
  double t_s = 0;
  std::string outcome;                 ///< "sent", "no_target", …
  double cmd_x = 0, cmd_y = 0, cmd_z = 0, cmd_qw = 1, cmd_qx = 0, cmd_qy = 0, cmd_qz = 0;
  double meas_x = 0, meas_y = 0, meas_z = 0, meas_qw = 1, meas_qx = 0, meas_qy = 0, meas_qz = 0;
};

struct TrialTelemetry {
  std::vector<HeadSample> head;    ///< by time
  std::vector<RobotSample> robot;  ///< by time
  std::uint64_t batches = 0, unsynced_batches = 0, undecodable_batches = 0;
};

/// ISO 8601 UTC ("2026-11-24T12:00:00.123Z") → ns since the epoch; nothing if it does not parse.
std::optional<std::int64_t> utcNs(const std::string& iso);

TrialTelemetry decodeTrialTelemetry(const std::vector<TelemetryBatch>& batches, std::int64_t trial_start_utc_ns);

/// `<stem>_head.csv` and `<stem>_robot.csv`; the paths written, or nothing with the reason.
std::optional<std::vector<std::string>> writeTrialTelemetryCsv(const TrialTelemetry& telemetry,
                                                               const std::string& path_stem, std::string* error);

}  // namespace telesphere::console::study
