// SPDX-License-Identifier: MIT
/// @brief TrialWorkflow (see trial_workflow.h).
#include "console/study/trial_workflow.h"

#include <cctype>
#include <cstdio>

#include "robot/link/proto_enums.h"
#include "robot/link/visual_mode.h"

namespace telesphere::console::study {
namespace {

std::optional<link::proto::VisualMode> visualModeOf(const std::string& mode) {
  const auto m = link::parseVisualMode(mode);
  return m ? std::optional(link::toProto(*m)) : std::nullopt;
}

}  // namespace

TrialWorkflow::TrialWorkflow(StudyStore& store, const SessionRecord& session, const StudyDefinition& study,
                             StudyRobot& robot)
    : store_(store), session_(session), study_(study), robot_(robot), db_uid_(store.uid()) {
  runner_ = std::make_unique<TrialRunner>(
      store_, session_, study_, [this](const std::string& mode, std::function<void(bool, const std::string&)> done) {
        const auto visual = visualModeOf(mode);
        if (!visual) return done(false, "unknown mode " + mode);
        say("switching the robot and the XR app to " + mode + " …");
        robot_.requestMode(*visual, [this, alive = std::weak_ptr<int>(alive_), mode, done](const StudyRobot::Reply& r) {
          if (alive.expired()) return;  // another participant or study since: nothing of ours is left
          if (!r.answered) return done(false, "the robot did not answer");
          if (!r.ok) return done(false, r.error);
          // The robot switched; the trial may start once the XR app renders in it too.
          pending_mode_ = PendingMode{mode, std::nullopt, done};
        });
      });
}

TrialWorkflow::~TrialWorkflow() = default;

std::string TrialWorkflow::recordingName(const std::string& participant, const std::string& mode,
                                         const std::string& db_uid, std::int64_t trial_id, int part) {
  std::string name = participant + "-" + mode + "-db" + (db_uid.empty() ? std::string("0") : db_uid) + "-t" +
                     std::to_string(trial_id);
  if (part > 1) name += "-part" + std::to_string(part);
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return name;
}

void TrialWorkflow::say(const std::string& text, bool error) { messages_.push_back({text, error}); }

std::vector<TrialWorkflow::Message> TrialWorkflow::takeMessages() {
  std::vector<Message> out;
  out.swap(messages_);
  return out;
}

void TrialWorkflow::noteRecording(std::int64_t trial_id, const std::string& note) {
  std::string error;
  if (!store_.addRecordingNote(trial_id, note, &error)) say("the recording note was not stored: " + error, true);
  say("trial recording: " + note, true);
}

bool TrialWorkflow::prepareNext() {
  if (!runner_->prepareNext()) {
    error_ = runner_->lastError();
    return false;
  }
  return true;
}

bool TrialWorkflow::start(std::int64_t now_ns) {
  if (!runner_->start(now_ns)) {
    error_ = runner_->lastError();
    return false;
  }
  recording_part_ = 1;
  robot_instance_ = robot_.robotInstance();
  sendIndicator(true, now_ns);
  say("trial running: " + runner_->mode());
  return true;
}

bool TrialWorkflow::attempt() {
  if (!runner_->attempt()) {
    error_ = runner_->lastError();
    return false;
  }
  return true;
}

bool TrialWorkflow::end(const std::function<bool()>& how) {
  if (runner_->state() == TrialRunner::State::kRunning && before_end_) before_end_();
  if (!how()) {
    error_ = runner_->lastError();
    return false;
  }
  return true;
}

bool TrialWorkflow::succeed(std::int64_t now_ns) {
  const bool ok = end([&] { return runner_->succeed(now_ns); });
  if (ok) tick(now_ns);
  return ok;
}

bool TrialWorkflow::fail(std::int64_t now_ns) {
  const bool ok = end([&] { return runner_->fail(now_ns); });
  if (ok) tick(now_ns);
  return ok;
}

bool TrialWorkflow::abort(std::int64_t now_ns, const std::string& reason) {
  const bool ok = end([&] { return runner_->abort(now_ns, reason); });
  if (ok) tick(now_ns);
  return ok;
}

void TrialWorkflow::interrupt(std::int64_t now_ns, const std::string& why) {
  if (runner_->state() != TrialRunner::State::kRunning) return;
  if (!end([&] { return runner_->interrupt(now_ns, why); })) say("the interruption was not stored: " + error_, true);
  if (indicator_on_) sendIndicator(false, now_ns);
}

bool TrialWorkflow::tick(std::int64_t now_ns) {
  // The mode gate: the robot acknowledged; the XR app must render in the mode within the timeout.
  if (pending_mode_) {
    if (!pending_mode_->deadline_ns)
      pending_mode_->deadline_ns = now_ns + static_cast<std::int64_t>(kModeSwitchTimeoutS * 1e9);
    const auto wanted = visualModeOf(pending_mode_->mode);
    const auto xr = robot_.xrVisualMode();
    if (xr && xr == wanted) {
      const std::string mode = pending_mode_->mode;
      const auto done = std::move(pending_mode_->done);
      pending_mode_.reset();
      done(true, "");
      say(mode + ": the robot and the XR app confirmed the mode; start the timer when the participant is ready");
    } else if (now_ns > *pending_mode_->deadline_ns) {
      const auto done = std::move(pending_mode_->done);
      pending_mode_.reset();
      done(false, xr ? "the XR app did not confirm the mode within 5 s"
                     : "the XR app is not connected (the participant would not see the mode)");
      say(runner_->lastError(), true);
    }
  }
  bool timed_out = false;
  const bool running = runner_->state() == TrialRunner::State::kRunning;
  if (running && runner_->elapsedS(now_ns) >= study_.time_limit_s) {
    timed_out = end([&] { return runner_->tick(now_ns); });
    if (timed_out) {
      char text[120];
      std::snprintf(text, sizeof text, "time limit (%g s) reached: the trial failed", study_.time_limit_s);
      say(text, true);
    }
  }
  const bool running_now = runner_->state() == TrialRunner::State::kRunning;
  if (running_now != indicator_on_) {
    sendIndicator(running_now, now_ns);
  } else if (running_now) {
    // A robot that restarted mid-trial knows nothing of it: the indicator again, a second part.
    const std::uint64_t instance = robot_.robotInstance();
    if (instance != 0 && robot_instance_ == 0) {
      robot_instance_ = instance;  // first heard of it after the start: the robot that took the indicator
    } else if (instance != 0 && instance != robot_instance_) {
      robot_instance_ = instance;
      ++recording_part_;
      char note[160];
      std::snprintf(note, sizeof note, "the robot restarted %.1f s into the trial: recording part %d from then on",
                    runner_->elapsedS(now_ns), recording_part_);
      noteRecording(runner_->trialId(), note);
      sendIndicator(true, now_ns);
    }
  }
  return timed_out;
}

void TrialWorkflow::sendIndicator(bool running, std::int64_t now_ns) {
  indicator_on_ = running;
  link::proto::TrialIndicator indicator;
  indicator.set_running(running);
  if (!running) {
    robot_.sendTrialIndicator(indicator, [](const StudyRobot::Reply&) {});
    return;
  }
  const std::int64_t trial_id = runner_->trialId();
  indicator.set_elapsed_s(runner_->elapsedS(now_ns));
  indicator.set_time_limit_s(study_.time_limit_s);
  // The robot records the trial under this name when it has a record folder (--record-dir).
  indicator.set_recording_name(recordingName(session_.participant, runner_->mode(), db_uid_, trial_id, recording_part_));
  indicator.set_study(study_.name);
  indicator.set_participant(session_.participant);
  indicator.set_trial_id(trial_id);
  indicator.set_mode(runner_->mode());
  indicator.set_study_database(db_uid_);
  robot_.sendTrialIndicator(indicator, [this, alive = std::weak_ptr<int>(alive_), trial_id](const StudyRobot::Reply& r) {
    if (alive.expired()) return;  // the workflow (and perhaps its database) is gone
    if (!r.answered) return noteRecording(trial_id, "the robot did not answer the trial indicator: not recorded");
    if (!r.ok) return noteRecording(trial_id, "the robot refused the trial indicator: " + r.error);
    if (!r.recording.available())
      return noteRecording(trial_id, "not recorded: the robot has no record folder (start it with --record-dir DIR)");
    if (!r.error.empty()) return noteRecording(trial_id, r.error);  // "the trial runs, but is not recorded: …"
    if (!r.recording.active() || r.recording.file().empty())
      return noteRecording(trial_id, "the robot records nothing for the trial");
    std::string error;
    if (!store_.addRecording(trial_id, r.recording.file(), &error))
      say("the trial's recording was not stored: " + error, true);
  });
}

}  // namespace telesphere::console::study
