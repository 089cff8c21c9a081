// SPDX-License-Identifier: MIT
/// @brief Plays a recorded session (LinkRecorder's topics) back onto a LinkServer at its
///        recorded pace, so that the unchanged XR app and console see the session again
///        (`telesphere-robot --replay FILE [--rate X] [--loop]`).
///
/// What the robot sent is sent again: stereo frames (the recorded JPEG bytes, joined from the
/// three messages of a frame by their sequence), robot state, telemetry and health. What clients
/// sent the robot (head targets, control requests, XR stats) is not replayed. A message goes out
/// at its log time mapped as t' = t_start + (t − t_first)/rate, where t_first is the recording's
/// first log time and t_start the replay's start (each loop starts anew); its robot-clock stamps
/// (every int64 `*_ns` field that holds a time on the robot's clock: capture, encode, joint
/// states, ticks) move with it by the same shift t' − t, so a client sees a live robot whose
/// clock agrees with its ping, and what is measured inside one message (capture → encoded →
/// sent, a batch's tick spacing) stays as recorded at any rate; operator-clock stamps and
/// durations are left as recorded. A frame's sent_ns is the link's own send time, as live.
///
/// The calibration the robot used is attached to a recording (at its start and at each change);
/// calibrationNow() is the one in use at the point the replay has reached, which the replaying
/// robot gives the XR app when it asks (get_calibration), as a live robot would.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "robot/link/link_server.h"
#include "robot/record/recording_reader.h"

namespace telesphere::record {

struct RecordingPlayerOptions {
  double rate = 1.0;  ///< > 0; 2: twice as fast
  bool loop = false;  ///< start again at the end, until stopped
};

struct RecordingPlayerStats {
  std::uint64_t frames = 0, states = 0, telemetry = 0, health = 0;
  std::uint64_t loops = 0;          ///< passes completed
  std::uint64_t skipped = 0;        ///< messages of topics not replayed, or frames missing an image
  double late_ms_max = 0.0;         ///< the most a message went out after its due time
};

class RecordingPlayer {
 public:
  /// Maps `path` and checks that it is a telesphere recording (its summary, or a scan when it
  /// has none, names /stereo/frame); null with the reason.
  static std::unique_ptr<RecordingPlayer> open(const std::string& path, std::string* error);

  /// Serves the recording on `server` until its end (every pass with `loop`) or `stop`. False
  /// with the reason when the file is damaged part way (what came before was served).
  bool run(link::LinkServer& server, const RecordingPlayerOptions& options, const std::atomic<bool>& stop,
           std::string* error);

  RecordingPlayerStats stats() const;
  const McapSummary& summary() const { return session_->summary(); }
  /// The calibration in use at the point the replay has reached (nothing: none attached yet, or
  /// a recording from before calibrations were attached). Any thread.
  std::optional<link::proto::CalibrationInUse> calibrationNow() const;

 private:
  explicit RecordingPlayer(std::unique_ptr<RecordingReader> session) : session_(std::move(session)) {}
  std::unique_ptr<RecordingReader> session_;
  std::atomic<std::uint64_t> states_{0}, telemetry_{0}, health_{0}, loops_{0}, not_replayed_{0};
  std::atomic<double> late_ms_max_{0.0};
  std::string path_;
  mutable std::mutex calibration_mutex_;
  std::optional<link::proto::CalibrationInUse> calibration_;
};

/// Moves every robot-clock time in `message` (int64 fields named *_ns, nonzero, except those that
/// hold operator-clock times or durations) by `shift_ns`; recursive.
void shiftRobotClockStamps(google::protobuf::Message* message, std::int64_t shift_ns);

}  // namespace telesphere::record
