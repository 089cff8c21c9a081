// SPDX-License-Identifier: MIT
/// @brief The study's durable record (DESIGN.md §7): SQLite through QtSql, WAL, one transaction
///        per event (session start, trial start, attempt, trial end, notes, each answer; the
///        trial's telemetry once a second), a
///        versioned schema migrated on open (PRAGMA user_version). Nothing entered is lost: a
///        closed window, Esc, a crash or kill -9 keep every committed event, and on the next open
///        every trial that was still running is ended as "interrupted" (an event says when).
///        One owner thread (QtSql connections belong to the thread that opened them).
#pragma once

#include <QSqlDatabase>
#include <QString>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "console/study/study_definition.h"

namespace telesphere::console::study {

/// How a trial ended.
enum class TrialOutcome { kRunning, kSuccess, kFail, kTimeout, kAbort, kInterrupted };
const char* trialOutcomeName(TrialOutcome outcome);  ///< "running", "success", "fail", …
std::optional<TrialOutcome> parseTrialOutcome(const std::string& name);

struct SessionRecord {
  std::int64_t id = 0;
  std::string participant;       ///< pseudonymous ID
  std::int64_t participant_index = 0;
  std::string study_name, study_json;
  std::vector<std::string> order;  ///< the modes in the order assigned
  std::string order_scheme;
  std::uint64_t seed = 0;
  std::string started_utc, ended_utc;  ///< ISO 8601; ended empty while open
};

struct TrialRecord {
  std::int64_t id = 0, session_id = 0;
  std::string participant;
  int order_index = 0;  ///< 0-based position in the session's order
  std::string mode;
  std::string started_utc, ended_utc;
  double duration_s = 0;  ///< set when it ended
  TrialOutcome outcome = TrialOutcome::kRunning;
  int attempts = 0;
  double time_limit_s = 0;
  std::string abort_reason, notes;
  std::string recording;  ///< the session recording the robot wrote for it (robot/record); empty: none
};

struct AnswerRecord {
  std::int64_t session_id = 0;
  std::string participant, mode, instrument, item;
  double value = 0;
  std::string answered_utc;
};

/// One telemetry envelope of the link (a serialized link::proto::Envelope: robot or XR
/// telemetry) kept with the trial it arrived during, with the mapping of the robot's clock to
/// UTC at that time (t_utc_ns = t_robot_ns + robot_to_utc_ns; none before the first pong).
struct TelemetryBatch {
  std::optional<std::int64_t> robot_to_utc_ns;
  std::string envelope;
};

class StudyStore {
 public:
  /// The schema this build writes; older files are migrated on open, newer ones refused.
  /// v1: sessions, trials, answers, events; v2: trial_telemetry; v3: trials.recording.
  static constexpr int kSchemaVersion = 3;

  /// Opens (creating or migrating) the database at `path`, then ends every trial still
  /// "running" as "interrupted". Nothing, with the reason, when it cannot.
  static std::unique_ptr<StudyStore> open(const std::string& path, std::string* error);
  ~StudyStore();
  StudyStore(const StudyStore&) = delete;
  StudyStore& operator=(const StudyStore&) = delete;

  /// Trials that open() found running and marked interrupted.
  const std::vector<TrialRecord>& interruptedOnOpen() const { return interrupted_; }

  /// A new session (participant, index, order stored with it); refused if the participant has
  /// one in this study already (resume it with findSession).
  std::optional<std::int64_t> startSession(const std::string& participant, std::int64_t participant_index,
                                           const StudyDefinition& study, const std::vector<std::string>& order,
                                           std::string* error);
  std::optional<SessionRecord> findSession(const std::string& participant, const std::string& study_name) const;
  bool endSession(std::int64_t session_id, std::string* error);

  std::optional<std::int64_t> startTrial(std::int64_t session_id, int order_index, const std::string& mode,
                                         double time_limit_s, std::string* error);
  bool addAttempt(std::int64_t trial_id, std::string* error);
  bool setNotes(std::int64_t trial_id, const std::string& notes, std::string* error);
  /// The recording the robot confirmed for the trial (its file, as the robot names it).
  bool setRecording(std::int64_t trial_id, const std::string& file, std::string* error);
  /// Ends a running trial; `duration_s` as the trial's own steady timer measured it.
  bool endTrial(std::int64_t trial_id, TrialOutcome outcome, double duration_s, const std::string& abort_reason,
                std::string* error);
  /// One answer, its own transaction; answering again replaces the value.
  bool saveAnswer(std::int64_t session_id, const std::string& mode, const std::string& instrument,
                  const std::string& item, double value, std::string* error);

  /// Telemetry that arrived during a trial, in one transaction (the console writes it once a
  /// second: a crash loses at most that second of telemetry, never an event or an answer).
  bool addTelemetry(std::int64_t trial_id, const std::vector<TelemetryBatch>& batches, std::string* error);
  std::vector<TelemetryBatch> telemetry(std::int64_t trial_id) const;  ///< in arrival order

  std::vector<SessionRecord> sessions() const;
  std::vector<TrialRecord> trials() const;    ///< by session, then order index
  std::vector<AnswerRecord> answers() const;  ///< by session, mode, instrument, item

  /// Imports rows as they are in the tidy CSV (sessions are created per participant as needed,
  /// with the study's definition); all or nothing.
  bool importRows(const StudyDefinition& study, const std::vector<TrialRecord>& trials,
                  const std::vector<AnswerRecord>& answers, std::string* error);

  /// A consistent copy of the whole database in one file (VACUUM INTO).
  bool copyTo(const std::string& path, std::string* error) const;

 private:
  explicit StudyStore(QString connection);
  bool migrate(std::string* error);
  bool markInterrupted(std::string* error);
  bool event(std::int64_t session_id, std::int64_t trial_id, const std::string& kind, const std::string& detail);

  QString connection_;
  std::vector<TrialRecord> interrupted_;
};

/// Now, UTC, ISO 8601 with milliseconds.
std::string utcNow();

}  // namespace telesphere::console::study
