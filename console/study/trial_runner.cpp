// SPDX-License-Identifier: MIT
/// @brief TrialRunner (see trial_runner.h).
#include "console/study/trial_runner.h"

#include <set>

namespace telesphere::console::study {

TrialRunner::TrialRunner(StudyStore& store, const SessionRecord& session, const StudyDefinition& study,
                         ModeRequest request_mode)
    : store_(store), session_(session), study_(study), request_mode_(std::move(request_mode)) {
  advance();
}

const std::string& TrialRunner::mode() const {
  static const std::string none;
  return position_ < static_cast<int>(session_.order.size()) ? session_.order[static_cast<std::size_t>(position_)]
                                                              : none;
}

void TrialRunner::advance() {
  std::set<int> finished;
  for (const TrialRecord& t : store_.trials())
    if (t.session_id == session_.id && t.outcome != TrialOutcome::kRunning && t.outcome != TrialOutcome::kInterrupted)
      finished.insert(t.order_index);
  position_ = 0;
  while (position_ < static_cast<int>(session_.order.size()) && finished.count(position_)) ++position_;
  state_ = position_ < static_cast<int>(session_.order.size()) ? State::kIdle : State::kDone;
}

bool TrialRunner::refuse(const std::string& why) {
  error_ = why;
  return false;
}

bool TrialRunner::prepareNext() {
  if (state_ != State::kIdle) return refuse(state_ == State::kDone ? "all trials are done" : "a trial is in progress");
  state_ = State::kSwitchingMode;
  error_.clear();
  const std::uint64_t generation = ++switch_generation_;
  request_mode_(mode(), [this, generation](bool ok, const std::string& error) {
    if (generation != switch_generation_ || state_ != State::kSwitchingMode) return;
    if (ok) {
      state_ = State::kReady;
    } else {
      state_ = State::kIdle;
      error_ = "the robot did not switch to " + mode() + ": " + (error.empty() ? "no reply" : error);
    }
  });
  return true;
}

bool TrialRunner::start(std::int64_t now_ns) {
  if (state_ != State::kReady) return refuse("start: the robot has not acknowledged the trial's mode yet");
  const auto id = store_.startTrial(session_.id, position_, mode(), study_.time_limit_s, &error_);
  if (!id) return false;
  trial_id_ = *id;
  started_ns_ = now_ns;
  state_ = State::kRunning;
  return true;
}

bool TrialRunner::attempt() {
  if (state_ != State::kRunning) return refuse("no trial is running");
  return store_.addAttempt(trial_id_, &error_);
}

double TrialRunner::elapsedS(std::int64_t now_ns) const {
  return state_ == State::kRunning ? double(now_ns - started_ns_) * 1e-9 : 0.0;
}

bool TrialRunner::end(TrialOutcome outcome, std::int64_t now_ns, const std::string& reason) {
  if (state_ != State::kRunning) return refuse("no trial is running");
  const double duration = outcome == TrialOutcome::kTimeout ? study_.time_limit_s : elapsedS(now_ns);
  if (!store_.endTrial(trial_id_, outcome, duration, reason, &error_)) return false;
  trial_id_ = 0;
  advance();
  return true;
}

bool TrialRunner::tick(std::int64_t now_ns) {
  if (state_ != State::kRunning || elapsedS(now_ns) < study_.time_limit_s) return false;
  return end(TrialOutcome::kTimeout, now_ns, "");
}

}  // namespace telesphere::console::study
