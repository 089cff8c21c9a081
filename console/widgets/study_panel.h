// SPDX-License-Identifier: MIT
/// @brief The study administrator's panel (paper §IV-B, DESIGN.md §1): opens a study file and its
///        database, starts or resumes a participant's session (the order assigned and stored),
///        runs the trials (the robot and the XR app switched to the trial's mode and both
///        acknowledging it before the timer can start; attempts, success, fail, abort with a
///        reason; the time limit fails the trial by itself; notes stored on every keystroke),
///        keeps each trial's telemetry with it, shows the operator in the headset that a trial
///        runs, then the questionnaire pages (one per mode) and the report. The trials' workflow
///        (mode gate, indicator, recordings, time limit) is study::TrialWorkflow, the sessions'
///        progress and the next questionnaire console/study/session_progress.h, the trial's
///        telemetry study::TrialTelemetryBuffer, all Qt-free; this panel shows them and forwards
///        the administrator's clicks. Every event is
///        committed as it happens (StudyStore): Esc does nothing here, closing the window ends a
///        running trial as interrupted, and after a crash the session resumes where it was.
///
///   pages: open study → participant → trials → questionnaires → done
///
/// One concept: the Study dock's pages, their widgets and what each click forwards (about 500
/// lines, most of them building and filling the five pages); the decisions are in console/study.
#pragma once

#include <QString>
#include <QTimer>
#include <QWidget>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "console/study/study_definition.h"
#include "console/study/study_store.h"
#include "console/study/trial_runner.h"
#include "console/study/trial_telemetry_buffer.h"
#include "console/study/trial_workflow.h"
#include "console/widgets/study_robot_session.h"

class QLabel;
class QLineEdit;
class QPlainTextEdit;
class QPushButton;
class QSpinBox;
class QStackedWidget;
class QTableWidget;

namespace telesphere::console {

class ConsoleSession;
class QuestionnairePage;

class StudyPanel : public QWidget {
  Q_OBJECT

 public:
  enum class Page { kOpen, kParticipant, kTrials, kQuestionnaire, kDone };
  /// How long the robot and the XR app get to confirm a mode switch.
  static constexpr double kModeSwitchTimeoutS = study::TrialWorkflow::kModeSwitchTimeoutS;
  /// Telemetry of a running trial is committed this often.
  static constexpr int kTelemetryFlushMs = 1000;

  explicit StudyPanel(ConsoleSession& session, QWidget* parent = nullptr);
  ~StudyPanel() override;

  /// Opens the study file (JSON; empty: the paper's study) and the database (created if new;
  /// trials it finds running are marked interrupted). False, with the reason shown, on failure.
  bool openStudy(const QString& study_file, const QString& database);
  /// A running trial ends as interrupted with `why`, buffered telemetry is committed (the
  /// window's close does this).
  void shutdown(const QString& why);

  Page page() const;
  study::StudyStore* store() const { return store_.get(); }
  const study::StudyDefinition& study() const { return study_; }
  const study::TrialRunner* runner() const { return workflow_ ? &workflow_->runner() : nullptr; }
  std::optional<study::SessionRecord> sessionRecord() const { return session_record_; }
  /// Trials that opening the database found running and marked interrupted.
  const std::vector<study::TrialRecord>& interruptedOnOpen() const;

  // The widgets, for the scripted tests and the screenshots.
  QLineEdit* participantEdit() const { return participant_; }
  QSpinBox* participantIndex() const { return participant_index_; }
  QPushButton* startSessionButton() const { return start_session_; }
  QPushButton* prepareButton() const { return prepare_; }
  QPushButton* startButton() const { return start_; }
  QPushButton* attemptButton() const { return attempt_; }
  QPushButton* successButton() const { return success_; }
  QPushButton* failButton() const { return fail_; }
  QLineEdit* abortReasonEdit() const { return abort_reason_; }
  QPushButton* abortButton() const { return abort_; }
  QPlainTextEdit* notesEdit() const { return notes_; }
  QLabel* statusLabel() const { return status_; }
  /// The status line as plain text (the last outcome or error).
  const QString& statusText() const { return status_text_; }
  QLabel* timerLabel() const { return timer_; }
  QuestionnairePage* questionnaire() const { return questionnaire_; }
  QPushButton* reportButton() const { return report_; }
  QPushButton* nextParticipantButton() const { return next_participant_; }
  /// Back to the participant page from the trials page (not while a trial runs).
  QPushButton* changeParticipantButton() const { return change_participant_; }
  /// Where "Write report" writes (default: next to the database).
  void setReportDirectory(const QString& dir) { report_dir_ = dir; }
  const QString& lastReport() const { return last_report_; }

  /// One step of the panel's timer (time limit, mode acknowledgement, telemetry, labels).
  void tick();

 private:
  void buildOpenPage();
  void buildParticipantPage();
  void buildTrialsPage();
  void buildDonePage();
  void startOrResume();
  void showPage(Page page);
  void endTrial(const std::function<bool(std::int64_t now_ns)>& end);
  void flushTelemetry();
  /// The workflow's news into the status line; the questionnaire once all trials are done.
  void afterWorkflow();
  void showQuestionnaire();
  void refresh();
  void setStatus(const QString& text, bool error = false);
  void writeReport();
  void toParticipantPage();
  void refreshSessions();

  ConsoleSession& session_;
  study::StudyDefinition study_;
  std::unique_ptr<study::StudyStore> store_;
  QString database_;
  std::optional<study::SessionRecord> session_record_;
  StudyRobotSession robot_;
  std::unique_ptr<study::TrialWorkflow> workflow_;  ///< the participant's trials (after store_: freed first)
  std::int64_t notes_trial_id_ = 0;  ///< the trial the notes box writes to
  int questionnaire_position_ = 0;   ///< index into the session's order
  study::TrialTelemetryBuffer telemetry_;  ///< the running trial's, until committed

  QStackedWidget* pages_;
  QLabel* open_hint_;
  QLabel* study_line_;
  QLineEdit* participant_;
  QSpinBox* participant_index_;
  QPushButton* start_session_;
  QTableWidget* sessions_table_;
  QLabel* trial_title_;
  QLabel* order_line_;
  QPushButton *prepare_, *start_, *attempt_, *success_, *fail_, *abort_;
  QLineEdit* abort_reason_;
  QPlainTextEdit* notes_;
  QLabel* timer_;
  QTableWidget* trials_table_;
  QWidget* questionnaire_holder_;
  QuestionnairePage* questionnaire_ = nullptr;
  QLabel* done_text_;
  QPushButton *report_, *next_participant_, *change_participant_;
  QLabel* status_;
  QString report_dir_, last_report_, status_text_;
  QTimer timer_tick_;
};

}  // namespace telesphere::console
