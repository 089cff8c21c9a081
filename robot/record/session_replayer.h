// SPDX-License-Identifier: MIT
/// @brief Plays a recorded session (SessionRecorder's topics) back onto a LinkServer at its
///        recorded pace, so that the unchanged XR app and console see the session again
///        (`telesphere-robot --replay FILE [--rate X] [--loop]`).
///
/// What the robot sent is sent again: stereo frames (the recorded JPEG bytes, joined from the
/// three messages of a frame by their sequence), robot state, telemetry and health. What clients
/// sent the robot (head targets, control requests, XR stats) is not replayed. Robot-clock stamps
/// (every int64 `*_ns` field that holds a time on the robot's clock: capture, encode, joint
/// states, ticks) are mapped as t' = t_start + (t − t_first)/rate, where t_first is the
/// recording's first log time and t_start the replay's start (each loop starts anew), so a client
/// sees a live robot whose clock agrees with its ping; operator-clock stamps and durations are
/// left as recorded. A frame's sent_ns is the link's own send time, as live.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "robot/link/link_server.h"
#include "robot/record/recorded_session.h"

namespace telesphere::record {

struct SessionReplayOptions {
  double rate = 1.0;  ///< > 0; 2: twice as fast
  bool loop = false;  ///< start again at the end, until stopped
};

struct SessionReplayStats {
  std::uint64_t frames = 0, states = 0, telemetry = 0, health = 0;
  std::uint64_t loops = 0;          ///< passes completed
  std::uint64_t skipped = 0;        ///< messages of topics not replayed, or frames missing an image
  double late_ms_max = 0.0;         ///< the most a message went out after its due time
};

class SessionReplayer {
 public:
  /// Maps `path` and checks that it is a telesphere recording (its summary, or a scan when it
  /// has none, names /stereo/frame); null with the reason.
  static std::unique_ptr<SessionReplayer> open(const std::string& path, std::string* error);

  /// Serves the recording on `server` until its end (every pass with `loop`) or `stop`. False
  /// with the reason when the file is damaged part way (what came before was served).
  bool run(link::LinkServer& server, const SessionReplayOptions& options, const std::atomic<bool>& stop,
           std::string* error);

  SessionReplayStats stats() const;
  const McapSummary& summary() const { return session_->summary(); }

 private:
  explicit SessionReplayer(std::unique_ptr<RecordedSession> session) : session_(std::move(session)) {}
  std::unique_ptr<RecordedSession> session_;
  std::atomic<std::uint64_t> states_{0}, telemetry_{0}, health_{0}, loops_{0}, not_replayed_{0};
  std::atomic<double> late_ms_max_{0.0};
};

/// Maps every robot-clock time in `message` (int64 fields named *_ns, nonzero, except those that
/// hold operator-clock times or durations) with t' = start + (t − first)/rate; recursive.
void mapRobotClockStamps(google::protobuf::Message* message, std::int64_t first_ns, std::int64_t start_ns, double rate);

}  // namespace telesphere::record
