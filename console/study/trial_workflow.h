// SPDX-License-Identifier: MIT
/// @brief A participant's trials as the administrator runs them, beside their record
///        (TrialRunner): the mode gate (the robot switches to the trial's mode and the XR app
///        confirms it within kModeSwitchTimeoutS before the timer may start), the trial indicator
///        the operator sees and the robot records by (one recording per trial, named uniquely
///        across study databases, a second part when the robot restarted mid-trial), the time
///        limit, and every refusal of the robot's shown and stored with the trial. Qt-free; the
///        Study panel only shows it and forwards the administrator's clicks.
///
///        Lifetimes: the workflow owns its runner. Replies of the robot may come after the
///        workflow is gone (another participant, another study): they hold only a weak token and
///        do nothing then, so nothing a reply touches can have been freed.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "console/study/study_definition.h"
#include "console/study/study_robot.h"
#include "console/study/study_store.h"
#include "console/study/trial_runner.h"

namespace telesphere::console::study {

class TrialWorkflow {
 public:
  /// How long the XR app gets to confirm a mode the robot switched to.
  static constexpr double kModeSwitchTimeoutS = 5.0;

  /// `store`, `study` and `robot` outlive the workflow; the session exists in `store`.
  TrialWorkflow(StudyStore& store, const SessionRecord& session, const StudyDefinition& study, StudyRobot& robot);
  ~TrialWorkflow();
  TrialWorkflow(const TrialWorkflow&) = delete;
  TrialWorkflow& operator=(const TrialWorkflow&) = delete;

  const TrialRunner& runner() const { return *runner_; }
  const SessionRecord& session() const { return session_; }

  // The administrator's actions at steady time now_ns; false with the reason in lastError().
  bool prepareNext();
  bool start(std::int64_t now_ns);
  bool attempt();
  bool succeed(std::int64_t now_ns);
  bool fail(std::int64_t now_ns);
  bool abort(std::int64_t now_ns, const std::string& reason);
  /// A running trial ends as interrupted with `why` (run again on resume) and the indicator goes
  /// off; nothing when none runs.
  void interrupt(std::int64_t now_ns, const std::string& why);
  const std::string& lastError() const { return error_; }

  /// Every ~100 ms: the mode gate, the time limit (true when it ended the trial now), the
  /// indicator in step with the trial, a restarted robot given the indicator again.
  bool tick(std::int64_t now_ns);

  /// Called just before a trial ends (the panel stores its buffered telemetry with it).
  void setBeforeTrialEnds(std::function<void()> f) { before_end_ = std::move(f); }

  /// What happened that the administrator should read, oldest first, taken once.
  struct Message {
    std::string text;
    bool error = false;
  };
  std::vector<Message> takeMessages();

  /// The recording name of a trial: participant, mode, the database's uid and the trial's id
  /// ("P07-full6d-db3f9a2c1-t12"), "-part2" and on for later parts; only letters, digits, - and _.
  static std::string recordingName(const std::string& participant, const std::string& mode, const std::string& db_uid,
                                   std::int64_t trial_id, int part);

 private:
  void say(const std::string& text, bool error = false);
  /// Stores why the trial is not (wholly) recorded and says it.
  void noteRecording(std::int64_t trial_id, const std::string& note);
  void sendIndicator(bool running, std::int64_t now_ns);
  bool end(const std::function<bool()>& how);

  StudyStore& store_;
  SessionRecord session_;
  StudyDefinition study_;
  StudyRobot& robot_;
  std::string db_uid_;
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);  ///< replies hold it weakly
  std::unique_ptr<TrialRunner> runner_;
  std::function<void()> before_end_;
  std::string error_;
  std::vector<Message> messages_;

  struct PendingMode {
    std::string mode;
    std::optional<std::int64_t> deadline_ns;  ///< set at the first tick after the robot's ack
    std::function<void(bool, const std::string&)> done;
  };
  std::optional<PendingMode> pending_mode_;
  bool indicator_on_ = false;        ///< what the robot was last told
  int recording_part_ = 0;           ///< of the running trial
  std::uint64_t robot_instance_ = 0;  ///< the robot that was told about the running trial
};

}  // namespace telesphere::console::study
