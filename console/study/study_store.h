// SPDX-License-Identifier: MIT
/// @brief The study's durable record (DESIGN.md §7): SQLite through QtSql, WAL, one transaction
///        per event (session start, trial start, attempt, trial end, notes, each answer; the
///        trial's telemetry once a second), a
///        versioned schema migrated on open (PRAGMA user_version). Nothing entered is lost: a
///        closed window, Esc, a crash or kill -9 keep every committed event, and on the next open
///        every trial that was still running is ended as "interrupted" (an event says when).
///        One owner thread (QtSql connections belong to the thread that opened them).
///
///        One writer: open() holds an advisory lock on `<database>.writer` (flock: the kernel
///        drops it when the process dies, however it dies) and writes who holds it there; a second
///        opener is refused with that text. Only the writer marks running trials interrupted, so a
///        trial that runs in another console is never touched. openSnapshot() reads a consistent
///        copy (VACUUM INTO through a read-only connection) and changes nothing in the file.
/// One concept: the study's SQLite record (about 650 lines) — the schema, its migration and every
/// read and write share one connection and one rule (one transaction per event); split, each part
/// would have to know that rule again.
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
  std::string recording;  ///< the session recordings the robot wrote for it (robot/record), "; "-separated; empty: none
  /// Why the trial is not (wholly) recorded, each cause as it happened ("the robot has no record
  /// folder", "the robot restarted at 12.3 s: recording part 2"), "; "-separated; empty: none.
  std::string recording_note;
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
  /// v1: sessions, trials, answers, events; v2: trial_telemetry; v3: trials.recording; v4: meta
  /// (the database's uid), trials.recording_note.
  static constexpr int kSchemaVersion = 4;

  /// Opens (creating or migrating) the database at `path` as its one writer, then ends every
  /// trial still "running" as "interrupted". Nothing, with the reason, when it cannot (another
  /// writer holds it: "… is open in telesphere-console (pid 4242 on rig-pc) since …").
  static std::unique_ptr<StudyStore> open(const std::string& path, std::string* error);
  /// A consistent snapshot of the database at `path` for reading (reports), as of now, while a
  /// writer may go on writing; nothing in `path` changes (the snapshot is a private temporary
  /// copy, migrated if older, removed with the store). Running trials stay "running" in it.
  static std::unique_ptr<StudyStore> openSnapshot(const std::string& path, std::string* error);
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
  /// A recording the robot confirmed for the trial (its file, as the robot names it), added to
  /// the ones it has (a robot restarted mid-trial records a second part).
  bool addRecording(std::int64_t trial_id, const std::string& file, std::string* error);
  /// Why the trial is not (wholly) recorded, added to what its row says already.
  bool addRecordingNote(std::int64_t trial_id, const std::string& note, std::string* error);
  /// This database's random id (8 hex digits, made when it was created or migrated to v4): with
  /// the trial's id it names the trial's recordings uniquely across databases.
  std::string uid() const;
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
  static std::unique_ptr<StudyStore> openConnection(const std::string& path, bool read_only, std::string* error);
  bool migrate(std::string* error);
  /// Appends `value` to a "; "-separated text column of a trial.
  bool appendToTrial(std::int64_t trial_id, const char* column, const std::string& value, const std::string& event_kind,
                     std::string* error);
  bool markInterrupted(std::string* error);
  bool event(std::int64_t session_id, std::int64_t trial_id, const std::string& kind, const std::string& detail);

  QString connection_;
  std::vector<TrialRecord> interrupted_;
  int writer_lock_fd_ = -1;     ///< open() holds `<database>.writer` locked while the store lives
  std::string snapshot_path_;   ///< openSnapshot(): the private copy, removed with the store
};

/// Now, UTC, ISO 8601 with milliseconds.
std::string utcNow();

}  // namespace telesphere::console::study
