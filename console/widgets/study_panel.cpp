// SPDX-License-Identifier: MIT
/// @brief StudyPanel (see study_panel.h).
#include "console/widgets/study_panel.h"

#include <cctype>

#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QSpinBox>
#include <QStackedWidget>
#include <QTableWidget>
#include <QVBoxLayout>
#include <map>

#include "console/widgets/console_session.h"
#include "console/supervision/visual_mode_label.h"
#include "console/widgets/questionnaire_page.h"
#include "console/study/study_report.h"
#include "console/study/session_progress.h"
#include "robot/link/link_endpoints.h"
#include "robot/link/proto_enums.h"

namespace telesphere::console {
namespace {

QString modeLabel(const std::string& mode) { return QString::fromStdString(supervision::visualModeLabel(mode, mode)); }

QString shortModeLabel(const std::string& mode) {
  const auto known = link::parseVisualMode(mode);
  const std::string_view label = known ? supervision::visualModeShortLabel(*known) : std::string_view(mode);
  return QString::fromUtf8(label.data(), static_cast<qsizetype>(label.size()));
}

QString clock(double s) {
  const int tenths = int(s * 10.0 + 0.5);
  return QString("%1:%2.%3").arg(tenths / 600, 2, 10, QChar('0')).arg(tenths / 10 % 60, 2, 10, QChar('0')).arg(tenths % 10);
}

QPushButton* button(const QString& text, const QString& name) {
  auto* b = new QPushButton(text);
  b->setObjectName(name);
  return b;
}

}  // namespace

StudyPanel::StudyPanel(ConsoleSession& session, QWidget* parent) : QWidget(parent), session_(session), robot_(session) {
  setObjectName("studyPanel");
  auto* layout = new QVBoxLayout(this);
  study_line_ = new QLabel("no study open");
  study_line_->setObjectName("studyLine");
  study_line_->setWordWrap(true);
  layout->addWidget(study_line_);
  pages_ = new QStackedWidget;
  layout->addWidget(pages_, 1);
  status_ = new QLabel;
  status_->setObjectName("studyStatus");
  status_->setWordWrap(true);
  status_->setTextFormat(Qt::RichText);
  layout->addWidget(status_);
  buildOpenPage();
  buildParticipantPage();
  buildTrialsPage();
  questionnaire_holder_ = new QWidget;
  new QVBoxLayout(questionnaire_holder_);
  pages_->addWidget(questionnaire_holder_);
  buildDonePage();
  showPage(Page::kOpen);

  session_.setTelemetryTap([this](const link::proto::Envelope& envelope, std::optional<std::int64_t> robot_to_console) {
    if (!workflow_ || workflow_->runner().state() != study::TrialRunner::State::kRunning) return;
    study::TelemetryBatch batch;
    if (robot_to_console) {  // console steady clock → UTC, now
      const std::int64_t steady_to_utc = QDateTime::currentMSecsSinceEpoch() * 1'000'000 - link::linkNowNs();
      batch.robot_to_utc_ns = *robot_to_console + steady_to_utc;
    }
    batch.envelope = envelope.SerializeAsString();
    telemetry_.add(std::move(batch));
  });
  timer_tick_.setInterval(100);
  connect(&timer_tick_, &QTimer::timeout, this, &StudyPanel::tick);
  timer_tick_.start();
}

StudyPanel::~StudyPanel() {
  session_.setTelemetryTap({});
  shutdown("the console closed during the trial");
}

const std::vector<study::TrialRecord>& StudyPanel::interruptedOnOpen() const {
  static const std::vector<study::TrialRecord> none;
  return store_ ? store_->interruptedOnOpen() : none;
}

void StudyPanel::buildOpenPage() {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  open_hint_ = new QLabel(
      "Open a study database to run sessions (a new file is created). The study file (JSON) says the modes, "
      "the order scheme, the time limit and the questionnaires; without one, the paper's study is run.");
  open_hint_->setWordWrap(true);
  layout->addWidget(open_hint_);
  auto* open = button("Open study…", "openStudy");
  connect(open, &QPushButton::clicked, this, [this] {
    const QString study = QFileDialog::getOpenFileName(this, "Study file (cancel: the paper's study)", {}, "Study (*.json)");
    const QString db = QFileDialog::getSaveFileName(this, "Study database", "study.sqlite", "SQLite (*.sqlite)",
                                                    nullptr, QFileDialog::DontConfirmOverwrite);
    if (!db.isEmpty()) openStudy(study, db);
  });
  layout->addWidget(open);
  layout->addStretch(1);
  pages_->addWidget(page);
}

void StudyPanel::buildParticipantPage() {
  auto* page = new QWidget;
  auto* form = new QFormLayout(page);
  participant_ = new QLineEdit;
  participant_->setObjectName("participantId");
  participant_->setPlaceholderText("pseudonymous ID, e.g. P07");
  form->addRow("Participant", participant_);
  participant_index_ = new QSpinBox;
  participant_index_->setObjectName("participantIndex");
  participant_index_->setRange(0, 100000);
  participant_index_->setToolTip("0-based; picks the counterbalanced order (index mod 6 for three modes)");
  form->addRow("Participant index", participant_index_);
  start_session_ = button("Start or resume session", "startSession");
  connect(start_session_, &QPushButton::clicked, this, &StudyPanel::startOrResume);
  connect(participant_, &QLineEdit::returnPressed, this, &StudyPanel::startOrResume);
  form->addRow(start_session_);
  sessions_table_ = new QTableWidget(0, 4);
  sessions_table_->setObjectName("sessionsTable");
  sessions_table_->setHorizontalHeaderLabels({"participant", "index", "order (6D, 3D, fixed)", "progress"});
  sessions_table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  sessions_table_->horizontalHeader()->setStretchLastSection(true);
  sessions_table_->verticalHeader()->setVisible(false);
  sessions_table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  sessions_table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  connect(sessions_table_, &QTableWidget::cellDoubleClicked, this, [this](int row, int) {
    participant_->setText(sessions_table_->item(row, 0)->text());
    startOrResume();
  });
  form->addRow(new QLabel("Sessions in this study (double-click to resume):"));
  form->addRow(sessions_table_);
  pages_->addWidget(page);
}

void StudyPanel::buildTrialsPage() {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  trial_title_ = new QLabel;
  trial_title_->setObjectName("trialTitle");
  trial_title_->setTextFormat(Qt::RichText);
  layout->addWidget(trial_title_);
  order_line_ = new QLabel;
  order_line_->setWordWrap(true);
  layout->addWidget(order_line_);
  timer_ = new QLabel("00:00.0");
  timer_->setObjectName("trialTimer");
  QFont big = timer_->font();
  big.setPointSizeF(big.pointSizeF() * 2.2);
  big.setBold(true);
  timer_->setFont(big);
  layout->addWidget(timer_);
  auto* row = new QHBoxLayout;
  prepare_ = button("Switch to mode", "prepareTrial");
  start_ = button("Start timer", "startTrial");
  attempt_ = button("Attempt +1", "attempt");
  success_ = button("Success", "success");
  fail_ = button("Fail", "fail");
  for (QPushButton* b : {prepare_, start_, attempt_, success_, fail_}) row->addWidget(b);
  layout->addLayout(row);
  auto* abort_row = new QHBoxLayout;
  abort_reason_ = new QLineEdit;
  abort_reason_->setObjectName("abortReason");
  abort_reason_->setPlaceholderText("reason to abort (required)");
  abort_ = button("Abort", "abortTrial");
  abort_row->addWidget(abort_reason_, 1);
  abort_row->addWidget(abort_);
  layout->addLayout(abort_row);
  layout->addWidget(new QLabel("Notes on this trial (stored as you type):"));
  notes_ = new QPlainTextEdit;
  notes_->setObjectName("trialNotes");
  notes_->setMaximumHeight(90);
  layout->addWidget(notes_);
  trials_table_ = new QTableWidget(0, 5);
  trials_table_->setObjectName("trialsTable");
  trials_table_->setHorizontalHeaderLabels({"#", "mode", "outcome", "duration [s]", "attempts"});
  trials_table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  trials_table_->horizontalHeader()->setSectionResizeMode(2, QHeaderView::Stretch);
  trials_table_->verticalHeader()->setVisible(false);
  trials_table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  layout->addWidget(trials_table_, 1);
  change_participant_ = button("Change participant", "changeParticipant");
  connect(change_participant_, &QPushButton::clicked, this, &StudyPanel::toParticipantPage);
  layout->addWidget(change_participant_, 0, Qt::AlignRight);

  connect(prepare_, &QPushButton::clicked, this, [this] {
    if (!workflow_) return;
    if (!workflow_->prepareNext()) setStatus(QString::fromStdString(workflow_->lastError()), true);
    afterWorkflow();
    refresh();
  });
  connect(start_, &QPushButton::clicked, this, [this] {
    if (!workflow_) return;
    if (!workflow_->start(link::linkNowNs())) {
      setStatus(QString::fromStdString(workflow_->lastError()), true);
    } else {
      notes_trial_id_ = workflow_->runner().trialId();
      const QSignalBlocker block(notes_);
      notes_->clear();
      telemetry_.start(workflow_->runner().trialId(), link::linkNowNs());
      afterWorkflow();
    }
    refresh();
  });
  connect(attempt_, &QPushButton::clicked, this, [this] {
    if (workflow_ && !workflow_->attempt()) setStatus(QString::fromStdString(workflow_->lastError()), true);
    refresh();
  });
  connect(success_, &QPushButton::clicked, this, [this] { endTrial([this](std::int64_t t) { return workflow_->succeed(t); }); });
  connect(fail_, &QPushButton::clicked, this, [this] { endTrial([this](std::int64_t t) { return workflow_->fail(t); }); });
  connect(abort_, &QPushButton::clicked, this, [this] {
    const std::string reason = abort_reason_->text().trimmed().toStdString();
    endTrial([this, reason](std::int64_t t) { return workflow_->abort(t, reason); });
    if (!workflow_ || workflow_->runner().state() != study::TrialRunner::State::kRunning) abort_reason_->clear();
  });
  connect(abort_reason_, &QLineEdit::textChanged, this, [this] { refresh(); });
  connect(notes_, &QPlainTextEdit::textChanged, this, [this] {
    if (!store_ || notes_trial_id_ == 0) return;
    std::string why;
    if (!store_->setNotes(notes_trial_id_, notes_->toPlainText().toStdString(), &why))
      setStatus("notes not stored: " + QString::fromStdString(why), true);
  });
  pages_->addWidget(page);
}

void StudyPanel::buildDonePage() {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  done_text_ = new QLabel;
  done_text_->setObjectName("sessionDone");
  done_text_->setWordWrap(true);
  done_text_->setTextFormat(Qt::RichText);
  layout->addWidget(done_text_);
  report_ = button("Write report (CSV, SQLite, Table I, plots)", "writeReport");
  connect(report_, &QPushButton::clicked, this, &StudyPanel::writeReport);
  next_participant_ = button("Next participant", "nextParticipant");
  connect(next_participant_, &QPushButton::clicked, this, &StudyPanel::toParticipantPage);
  layout->addWidget(report_);
  layout->addWidget(next_participant_);
  layout->addStretch(1);
  pages_->addWidget(page);
}

bool StudyPanel::openStudy(const QString& study_file, const QString& database) {
  study::StudyDefinition definition;
  definition.questionnaires = {study::paperLikert()};
  if (!study_file.isEmpty()) {
    QFile f(study_file);
    if (!f.open(QIODevice::ReadOnly)) {
      setStatus("cannot read the study file " + study_file, true);
      return false;
    }
    std::string why;
    const auto parsed = study::StudyDefinition::parse(f.readAll().toStdString(), &why);
    if (!parsed) {
      setStatus(study_file + ": " + QString::fromStdString(why), true);
      return false;
    }
    definition = *parsed;
  }
  std::string why;
  auto store = study::StudyStore::open(database.toStdString(), &why);
  if (!store) {
    setStatus(QString::fromStdString(why), true);
    return false;
  }
  shutdown("another study was opened during the trial");
  workflow_.reset();  // before the store it writes into; its late replies then find nothing
  session_record_.reset();
  store_ = std::move(store);
  study_ = definition;
  database_ = database;
  const int in_study = static_cast<int>(study::sessionsOfStudy(*store_, study_).size());
  participant_index_->setValue(in_study);
  QStringList modes;
  for (const std::string& m : study_.modes) modes << modeLabel(m);
  study_line_->setText(QString("<b>Study %1</b> · %2 · %3 · %4 s per trial · %5")
                           .arg(QString::fromStdString(study_.name), modes.join(", "),
                                study_.order == study::OrderScheme::kCounterbalanced ? "counterbalanced"
                                                                                     : "seeded random",
                                QString::number(study_.time_limit_s), QFileInfo(database).fileName()));
  QString status = QString("%1 session(s) in this study").arg(in_study);
  if (!store_->interruptedOnOpen().empty())
    status += QString(" · %1 trial(s) were running when the console stopped: marked interrupted, run again on resume")
                  .arg(store_->interruptedOnOpen().size());
  setStatus(status);
  refreshSessions();
  showPage(Page::kParticipant);
  return true;
}

void StudyPanel::startOrResume() {
  if (!store_) return;
  const std::string participant = participant_->text().trimmed().toStdString();
  bool resumed = false;
  std::string why;
  const std::optional<study::SessionRecord> record = study::startOrResumeSession(
      *store_, study_, participant, std::uint64_t(participant_index_->value()), &resumed, &why);
  if (!record) {
    setStatus(QString::fromStdString(why), true);
    return;
  }
  const QString what = resumed ? "resumed" : "started";
  session_record_ = record;
  workflow_.reset();
  workflow_ = std::make_unique<study::TrialWorkflow>(*store_, *record, study_, robot_);
  workflow_->setBeforeTrialEnds([this] { flushTelemetry(); });
  QStringList order;
  for (const std::string& m : record->order) order << modeLabel(m);
  order_line_->setText(QString("Order: %1 (%2, participant index %3, seed %4)")
                           .arg(order.join(" → "), QString::fromStdString(record->order_scheme))
                           .arg(record->participant_index)
                           .arg(record->seed));
  notes_trial_id_ = 0;
  setStatus(QString("session %1 for participant %2").arg(what, QString::fromStdString(participant)));
  if (workflow_->runner().state() == study::TrialRunner::State::kDone) {
    showQuestionnaire();
  } else {
    showPage(Page::kTrials);
    refresh();
  }
}

void StudyPanel::endTrial(const std::function<bool(std::int64_t now_ns)>& end) {
  if (!workflow_) return;
  if (!end(link::linkNowNs())) {
    setStatus(QString::fromStdString(workflow_->lastError()), true);
  } else {
    setStatus("trial ended");
    afterWorkflow();
  }
  refresh();
}

void StudyPanel::flushTelemetry() {
  if (!store_) return;
  std::string why;
  if (!telemetry_.flush(*store_, link::linkNowNs(), &why))
    setStatus("telemetry not stored: " + QString::fromStdString(why), true);
}

void StudyPanel::afterWorkflow() {
  if (!workflow_) return;
  for (const auto& m : workflow_->takeMessages()) setStatus(QString::fromStdString(m.text), m.error);
  if (workflow_->runner().state() == study::TrialRunner::State::kDone && page() == Page::kTrials) showQuestionnaire();
}

void StudyPanel::tick() {
  if (workflow_) {
    if (workflow_->runner().state() == study::TrialRunner::State::kRunning &&
        telemetry_.due(link::linkNowNs(), std::int64_t(kTelemetryFlushMs) * 1'000'000))
      flushTelemetry();
    workflow_->tick(link::linkNowNs());
    afterWorkflow();
  }
  refresh();
}

void StudyPanel::showQuestionnaire() {
  if (!session_record_) return;
  // The first mode, in the session's order, whose page is not complete.
  std::map<std::pair<std::string, std::string>, double> given;
  const auto answers = store_->answers();
  questionnaire_position_ = static_cast<int>(study::nextQuestionnaire(*session_record_, study_, answers));
  if (study_.questionnaires.empty() || questionnaire_position_ >= static_cast<int>(session_record_->order.size())) {
    std::string why;
    if (session_record_->ended_utc.empty() && !store_->endSession(session_record_->id, &why))
      setStatus("session end not stored: " + QString::fromStdString(why), true);
    done_text_->setText(QString("<b>Session complete</b> for participant %1: %2 trials and the questionnaires "
                                "are stored in %3.")
                            .arg(QString::fromStdString(session_record_->participant))
                            .arg(session_record_->order.size())
                            .arg(QFileInfo(database_).fileName()));
    showPage(Page::kDone);
    return;
  }
  const std::string mode = session_record_->order[std::size_t(questionnaire_position_)];
  for (const study::AnswerRecord& a : answers)
    if (a.session_id == session_record_->id && a.mode == mode) given[{a.instrument, a.item}] = a.value;
  if (questionnaire_) questionnaire_->deleteLater();
  questionnaire_ = new QuestionnairePage(
      *store_, session_record_->id, mode,
      QString("Questionnaire %1 of %2 — %3 (participant %4)")
          .arg(questionnaire_position_ + 1)
          .arg(session_record_->order.size())
          .arg(modeLabel(mode), QString::fromStdString(session_record_->participant)),
      study_.questionnaires, given);
  questionnaire_holder_->layout()->addWidget(questionnaire_);
  connect(questionnaire_, &QuestionnairePage::saved, this, [this] { showQuestionnaire(); });
  showPage(Page::kQuestionnaire);
}

void StudyPanel::writeReport() {
  if (!store_) return;
  const QString dir = !report_dir_.isEmpty() ? report_dir_ : database_ + "-report";
  std::string why;
  const auto files = study::writeStudyReport(*store_, dir.toStdString(), &why);
  if (!files) {
    setStatus("report not written: " + QString::fromStdString(why), true);
    return;
  }
  last_report_ = dir;
  setStatus(QString("report: %1 files in %2").arg(files->size()).arg(dir));
}

void StudyPanel::shutdown(const QString& why) {
  if (!workflow_ || workflow_->runner().state() != study::TrialRunner::State::kRunning || !store_) return;
  workflow_->interrupt(link::linkNowNs(), why.toStdString());
  workflow_.reset();
  toParticipantPage();  // the session resumes from there, the interrupted trial run again
}

void StudyPanel::toParticipantPage() {
  if (workflow_ && workflow_->runner().state() == study::TrialRunner::State::kRunning) return;
  workflow_.reset();  // a mode switch still pending answers into nothing
  session_record_.reset();
  notes_trial_id_ = 0;
  participant_->clear();
  const int in_study = store_ ? static_cast<int>(study::sessionsOfStudy(*store_, study_).size()) : 0;
  participant_index_->setValue(in_study);  // the next counterbalanced order
  refreshSessions();
  showPage(Page::kParticipant);
}

void StudyPanel::refreshSessions() {
  if (!store_) return;
  const auto trials = store_->trials();
  const auto answers = store_->answers();
  const std::vector<study::SessionRecord> sessions = study::sessionsOfStudy(*store_, study_);
  sessions_table_->setRowCount(static_cast<int>(sessions.size()));
  for (std::size_t r = 0; r < sessions.size(); ++r) {
    const study::SessionRecord& s = sessions[r];
    const study::SessionProgress p = study::sessionProgress(s, study_, trials, answers);
    QStringList order;  // short: the column must fit beside the others
    for (const std::string& m : s.order) order << shortModeLabel(m);
    const QString progress = p.complete ? "complete"
                                        : QString("%1/%2 trials, %3/%4 answers")
                                              .arg(p.trials_finished)
                                              .arg(p.trials)
                                              .arg(p.answers)
                                              .arg(p.answers_needed);
    const QStringList cells = {QString::fromStdString(s.participant), QString::number(s.participant_index),
                               order.join(" → "), progress};
    for (int c = 0; c < cells.size(); ++c) sessions_table_->setItem(int(r), c, new QTableWidgetItem(cells[c]));
  }
}

StudyPanel::Page StudyPanel::page() const { return static_cast<Page>(pages_->currentIndex()); }

void StudyPanel::showPage(Page page) { pages_->setCurrentIndex(static_cast<int>(page)); }

void StudyPanel::setStatus(const QString& text, bool error) {
  status_text_ = text;
  status_->setText(error ? "<b style='color:#b3261e'>" + text.toHtmlEscaped() + "</b>" : text.toHtmlEscaped());
}

void StudyPanel::refresh() {
  if (!workflow_ || !session_record_) return;
  const study::TrialRunner& runner = workflow_->runner();
  using State = study::TrialRunner::State;
  const State state = runner.state();
  const int n = static_cast<int>(session_record_->order.size());
  const QString who = QString::fromStdString(session_record_->participant);
  if (state == State::kDone)
    trial_title_->setText("<b>" + who + "</b>: all trials done");
  else
    trial_title_->setText(QString("<b>%1</b>: trial %2 of %3 — <b>%4</b>")
                              .arg(who)
                              .arg(runner.orderIndex() + 1)
                              .arg(n)
                              .arg(modeLabel(runner.mode())));
  const double elapsed = runner.elapsedS(link::linkNowNs());
  timer_->setText(clock(elapsed) + " / " + clock(study_.time_limit_s) +
                  (state == State::kSwitchingMode ? "   switching mode…"
                   : state == State::kReady       ? "   ready"
                   : state == State::kRunning     ? "   running"
                                                  : ""));
  prepare_->setEnabled(state == State::kIdle);
  start_->setEnabled(state == State::kReady);
  for (QPushButton* b : {attempt_, success_, fail_}) b->setEnabled(state == State::kRunning);
  abort_->setEnabled(state == State::kRunning && !abort_reason_->text().trimmed().isEmpty());
  notes_->setEnabled(notes_trial_id_ != 0);
  change_participant_->setEnabled(state != State::kRunning);
  const auto trials = store_->trials();
  int rows = 0;
  for (const study::TrialRecord& t : trials) rows += t.session_id == session_record_->id;
  trials_table_->setRowCount(rows);
  int r = 0;
  for (const study::TrialRecord& t : trials) {
    if (t.session_id != session_record_->id) continue;
    const QString outcome = QString(study::trialOutcomeName(t.outcome)) +
                            (t.abort_reason.empty() ? "" : ": " + QString::fromStdString(t.abort_reason));
    const double duration = t.outcome == study::TrialOutcome::kRunning ? elapsed : t.duration_s;
    const QStringList cells = {QString::number(t.order_index + 1), modeLabel(t.mode), outcome,
                               QString::number(duration, 'f', 1), QString::number(t.attempts)};
    for (int c = 0; c < cells.size(); ++c) trials_table_->setItem(r, c, new QTableWidgetItem(cells[c]));
    ++r;
  }
}

}  // namespace telesphere::console
