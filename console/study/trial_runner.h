// SPDX-License-Identifier: MIT
/// @brief One participant's trials, in the order assigned (paper §IV-B): before each trial the
///        robot (and through it the XR app) is switched to the trial's visual mode and the runner
///        waits for the robot's acknowledgement; then the administrator starts the timer, counts
///        attempts and ends the trial as success, fail or abort (with a reason); the time limit
///        ends it as a timeout. Every step is written to the StudyStore as it happens. Time comes
///        from the caller (steady ns), so tests drive it. A session resumed after a crash goes on
///        with the first position in the order that has no finished trial (interrupted ones are
///        run again).
///
///   kIdle --prepareNext--> kSwitchingMode --ack ok--> kReady --start--> kRunning
///   kRunning --succeed/fail/abort/time limit--> kIdle (next) … kDone after the last position.
///   A refused or failed mode switch goes back to kIdle with the reason in lastError().
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "console/study/study_definition.h"
#include "console/study/study_store.h"

namespace telesphere::console::study {

/// Asks the robot for a visual mode; `done(ok, error)` is called once with its reply (later or at once).
using ModeRequest = std::function<void(const std::string& mode, std::function<void(bool ok, const std::string& error)> done)>;

class TrialRunner {
 public:
  enum class State { kIdle, kSwitchingMode, kReady, kRunning, kDone };

  /// The session must exist in `store`; both outlive the runner.
  TrialRunner(StudyStore& store, const SessionRecord& session, const StudyDefinition& study, ModeRequest request_mode);

  State state() const { return state_; }
  /// The order position the runner is at, and its mode (valid unless kDone).
  int orderIndex() const { return position_; }
  const std::string& mode() const;
  const std::string& lastError() const { return error_; }
  /// The running trial's id in the store (0 unless kRunning).
  std::int64_t trialId() const { return trial_id_; }

  /// Switches the robot to the next position's mode; false (with the reason) unless kIdle.
  bool prepareNext();
  /// Starts the timer of the prepared trial (kReady) and records the start.
  bool start(std::int64_t now_ns);
  bool attempt();
  bool succeed(std::int64_t now_ns) { return end(TrialOutcome::kSuccess, now_ns, ""); }
  bool fail(std::int64_t now_ns) { return end(TrialOutcome::kFail, now_ns, ""); }
  bool abort(std::int64_t now_ns, const std::string& reason) { return end(TrialOutcome::kAbort, now_ns, reason); }
  /// Ends a running trial as interrupted (the console closes, another study opens): it is run
  /// again when the session resumes.
  bool interrupt(std::int64_t now_ns, const std::string& why) { return end(TrialOutcome::kInterrupted, now_ns, why); }
  /// Ends a running trial as a timeout once the time limit has passed; true if it did.
  bool tick(std::int64_t now_ns);
  /// Seconds since start() (0 unless running).
  double elapsedS(std::int64_t now_ns) const;

 private:
  bool end(TrialOutcome outcome, std::int64_t now_ns, const std::string& reason);
  bool refuse(const std::string& why);
  void advance();  ///< position_ to the first order position without a finished trial

  StudyStore& store_;
  SessionRecord session_;
  StudyDefinition study_;
  ModeRequest request_mode_;
  State state_ = State::kIdle;
  int position_ = 0;
  std::int64_t trial_id_ = 0, started_ns_ = 0;
  std::uint64_t switch_generation_ = 0;  ///< replies to an older request are ignored
  std::string error_;
};

}  // namespace telesphere::console::study
