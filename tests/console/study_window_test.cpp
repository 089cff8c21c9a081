// SPDX-License-Identifier: MIT
/// @brief A study run through the console's real widgets (offscreen) against real
///        telesphere-robot and telesphere-xr offscreen processes on loopback (paper §IV-B):
///        twelve participants' orders balanced; a whole session — each trial's mode switched on
///        the robot and confirmed by the XR app before the timer may start, attempts, notes,
///        success, abort with a reason, the time limit, the trial indicator drawn in the
///        headset, each trial's telemetry stored with it — then the questionnaire pages
///        (complete before save) and the report; Esc and closing the window; a console killed
///        with SIGKILL during a trial and during a questionnaire, reopened: nothing lost.
///        Screenshots of each page into $TELESPHERE_SCREENSHOT_DIR or build/console-screenshots.
#include <gtest/gtest.h>

#include <QDateTime>
#include <QDockWidget>
#include <QFileInfo>
#include <QImage>
#include <QKeyEvent>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QSpinBox>
#include <QTabWidget>
#include <map>
#include <set>

#include "console/widgets/questionnaire_page.h"
#include "console/study/study_definition.h"
#include "console/study/trial_order.h"
#include "console/study/trial_telemetry.h"
#include "console/widgets/study_panel.h"
#include "robot/link/telesphere_link.pb.h"
#include "tests/console/console_rig.h"
#include "xr/frame_loop/trial_indicator.h"

namespace telesphere::console {
namespace {

using namespace test_rig;
using study::TrialOutcome;

QString writeStudy(const QTemporaryDir& dir, double time_limit_s) {
  const QString path = dir.filePath("study.json");
  QFile f(path);
  EXPECT_TRUE(f.open(QIODevice::WriteOnly));
  f.write(QString(R"({"name": "peg", "order": "counterbalanced", "time_limit_s": %1,
                       "questionnaires": {"paper_likert": true}})")
              .arg(time_limit_s)
              .toUtf8());
  return path;
}

/// Shows the study dock in front and grabs it.
void shootStudy(Rig& rig, const QString& name) {
  QDockWidget* dock = rig.window->dockOf(rig.window->studyPanel());
  dock->show();
  dock->raise();
  pumpFor(150);
  saveShot(dock, name);
}

void answerPage(QuestionnairePage* page, int first_value) {
  int i = 0;
  for (const study::QuestionnaireItem& item : study::paperLikert().items)
    ASSERT_TRUE(page->answer("paper_likert", item.key, 1 + (first_value + i++) % 7));
}

/// The XR display frames stored with a trial that had the trial indicator drawn.
std::size_t framesWithIndicator(const std::vector<study::TelemetryBatch>& batches) {
  std::size_t n = 0;
  for (const auto& b : batches) {
    link::proto::Envelope e;
    if (!e.ParseFromString(b.envelope) || !e.has_xr_telemetry()) continue;
    for (const auto& f : e.xr_telemetry().frames()) n += f.trial_indicator_shown();
  }
  return n;
}

TEST(StudyWindow, TwelveParticipantsGetBalancedOrdersThroughThePanel) {
  Rig rig(27930);  // no robot needed: no trial is run
  StudyPanel* panel = rig.window->studyPanel();
  ASSERT_TRUE(panel->openStudy(writeStudy(rig.dir, 300), rig.dir.filePath("orders.sqlite")))
      << panel->statusText().toStdString();
  std::map<std::vector<std::string>, int> orders;
  std::map<std::pair<int, std::string>, int> position_counts;
  for (int p = 0; p < 12; ++p) {
    ASSERT_EQ(panel->page(), StudyPanel::Page::kParticipant);
    EXPECT_EQ(panel->participantIndex()->value(), p);  // the next index is proposed
    panel->participantEdit()->setText(QString("P%1").arg(p + 1, 2, 10, QChar('0')));
    panel->startSessionButton()->click();
    ASSERT_EQ(panel->page(), StudyPanel::Page::kTrials) << panel->statusText().toStdString();
    const auto record = panel->sessionRecord();
    ASSERT_TRUE(record);
    ASSERT_EQ(record->order.size(), 3u);
    ++orders[record->order];
    for (int i = 0; i < 3; ++i) ++position_counts[{i, record->order[std::size_t(i)]}];
    panel->changeParticipantButton()->click();
  }
  EXPECT_EQ(orders.size(), 6u);  // all 3! orders, each twice
  for (const auto& [order, n] : orders) EXPECT_EQ(n, 2);
  for (const auto& [key, n] : position_counts) EXPECT_EQ(n, 4) << "mode " << key.second << " at " << key.first;
  // The same participant again resumes, never a second session.
  panel->participantEdit()->setText("P03");
  panel->startSessionButton()->click();
  EXPECT_EQ(panel->sessionRecord()->participant_index, 2);
  EXPECT_EQ(panel->store()->sessions().size(), 12u);
}

TEST(StudyWindow, NasaTlxAndSusPagesStartUnansweredAndStoreEachAnswer) {
  QTemporaryDir dir;
  std::string error;
  auto store = study::StudyStore::open(dir.filePath("q.sqlite").toStdString(), &error);
  ASSERT_TRUE(store) << error;
  study::StudyDefinition definition;
  const auto session = store->startSession("P09", 0, definition, definition.modes, &error);
  ASSERT_TRUE(session) << error;
  const std::vector<study::Questionnaire> instruments = {study::nasaTlxRaw(), study::systemUsabilityScale()};
  // An answer given before a crash comes back on the page.
  ASSERT_TRUE(store->saveAnswer(*session, "fixed", "sus", "q1", 4, &error));
  QuestionnairePage page(*store, *session, "fixed", "fixed perspective", instruments, {{{"sus", "q1"}, 4.0}});
  page.resize(700, 900);
  EXPECT_EQ(page.itemCount(), 16);  // 6 TLX subscales + 10 SUS items
  EXPECT_EQ(page.answeredCount(), 1);
  // A TLX answer of 0 is an answer (the spin box's "not answered" is below the scale).
  for (const auto& item : study::nasaTlxRaw().items) ASSERT_TRUE(page.answer("nasa_tlx_raw", item.key, 0));
  EXPECT_FALSE(page.saveButton()->isEnabled());
  for (const auto& item : study::systemUsabilityScale().items) ASSERT_TRUE(page.answer("sus", item.key, 5));
  EXPECT_FALSE(page.answer("sus", "q1", 6));  // off the 1–5 scale: no such button
  EXPECT_TRUE(page.saveButton()->isEnabled());
  EXPECT_TRUE(page.lastError().isEmpty());
  std::map<std::string, double> stored;
  for (const auto& a : store->answers()) stored[a.instrument + "." + a.item] = a.value;
  EXPECT_EQ(stored.size(), 16u);
  EXPECT_EQ(stored["nasa_tlx_raw." + study::nasaTlxRaw().items[0].key], 0.0);
  EXPECT_EQ(stored["sus.q1"], 5.0);
  saveShot(&page, "study_questionnaire_tlx_sus.png");
}

TEST(StudyWindow, AWholeSessionFromModeSwitchToReport) {
  Rig rig(27940);
  rig.startRobot();
  // The demo look-around (yaw ±30°, pitch ±10°, a 10 cm side step at 1.6 m), eyes written as PNG.
  const QString eyes = rig.dir.filePath("eyes");
  rig.startXr(false, {"--out", eyes, "--png-every", "10"}, "240x240");
  ASSERT_TRUE(pumpUntil([&] { return rig.connected(); }, 60000)) << rig.logs();
  StudyPanel* panel = rig.window->studyPanel();
  const double limit_s = 4.0;
  ASSERT_TRUE(panel->openStudy(writeStudy(rig.dir, limit_s), rig.dir.filePath("study.sqlite")));
  shootStudy(rig, "study_participant.png");
  panel->participantEdit()->setText("P05");
  panel->participantIndex()->setValue(4);
  panel->startSessionButton()->click();
  ASSERT_EQ(panel->page(), StudyPanel::Page::kTrials);
  study::StudyDefinition definition;
  const std::vector<std::string> order = study::trialOrder(definition, 4);
  ASSERT_EQ(panel->sessionRecord()->order, order);
  EXPECT_FALSE(panel->startButton()->isEnabled());  // not before the mode is confirmed

  const auto prepare = [&](const std::string& mode) {
    rig.click(panel->prepareButton());
    ASSERT_TRUE(pumpUntil([&] { return panel->startButton()->isEnabled(); })) << panel->statusText().toStdString();
    // Both ends run the trial's mode: the robot's state and what the XR app renders with.
    const auto wanted = mode == "full6d"          ? link::proto::VISUAL_MODE_FULL6D
                        : mode == "orientation3d" ? link::proto::VISUAL_MODE_ORIENTATION3D
                                                  : link::proto::VISUAL_MODE_FIXED;
    EXPECT_TRUE(pumpUntil([&] { return rig.session->robotState() && rig.session->robotState()->visual_mode() == wanted; }));
    EXPECT_EQ(rig.session->telemetry().xrVisualMode(), wanted);
  };

  // Trial 1: two attempts, notes, success.
  prepare(order[0]);
  rig.click(panel->startButton());
  // From when the robot has the trial, the XR app (which follows the robot's state as this console
  // does) draws the indicator.
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robotState() && rig.session->robotState()->trial().running(); }));
  const QDateTime indicator_on = QDateTime::currentDateTime();
  rig.click(panel->attemptButton());
  rig.click(panel->attemptButton());
  panel->notesEdit()->setFocus();
  panel->notesEdit()->insertPlainText("dropped the peg once");
  pumpFor(1500);
  shootStudy(rig, "study_trial_running.png");
  {  // What the operator sees meanwhile: the trial indicator low in each eye's view.
    // The first eye PNG written whole (views.csv lists a PNG once it is) at least 0.5 s after the
    // robot had the trial. Not the newest but one: that is 0.33–0.67 s old at 30 Hz (a PNG every 10
    // frames), but the XR app under the sanitizers beside another test runs slower (17 Hz seen on
    // CI), and one CI run's newest but one was drawn before the trial began (the bar empty).
    QString shown_png;
    const auto findShown = [&] {
      QFile csv(eyes + "/views.csv");
      if (!csv.open(QIODevice::ReadOnly)) return false;
      while (!csv.atEnd()) {
        const QString png = QString::fromUtf8(csv.readLine()).section(',', 0, 0);
        if (png.startsWith("eyes_") && QFileInfo(eyes + "/" + png).lastModified() >= indicator_on.addMSecs(500)) {
          shown_png = eyes + "/" + png;
          return true;
        }
      }
      return false;
    };
    ASSERT_TRUE(pumpUntil(findShown, 2000)) << "no eye PNG written 0.5 s into the trial or later";
    const QImage view(shown_png);
    ASSERT_EQ(view.size(), QSize(480, 240));
    const xr::frame_loop::TrialIndicatorGeometry g = xr::frame_loop::trialIndicatorGeometry(240, 240);
    const int row = 240 - 1 - (g.y + g.height / 2);  // GL rows count from the bottom
    for (int eye = 0; eye < 2; ++eye) {
      const QColor filled = view.pixelColor(eye * 240 + g.x + 1, row);  // the bar's first second
      EXPECT_GT(filled.green(), 150) << "eye " << eye;
      EXPECT_LT(filled.red(), 100) << "eye " << eye;
      const QColor empty = view.pixelColor(eye * 240 + g.x + g.width - 2, row);  // 0.5–3.7 of 4 s: not yet
      EXPECT_NEAR(empty.green(), 64, 3) << "eye " << eye;
    }
    QFile::remove(screenshotDir() + "/study_headset_trial_indicator.png");
    QFile::copy(shown_png, screenshotDir() + "/study_headset_trial_indicator.png");
  }
  // Esc on the panel and its notes changes nothing: the trial still runs.
  for (QWidget* w : {static_cast<QWidget*>(panel), static_cast<QWidget*>(panel->notesEdit())}) {
    QKeyEvent esc(QEvent::KeyPress, Qt::Key_Escape, Qt::NoModifier);
    QApplication::sendEvent(w, &esc);
  }
  pumpFor(200);
  EXPECT_TRUE(panel->successButton()->isEnabled());
  EXPECT_TRUE(rig.window->isVisible());
  rig.click(panel->successButton());

  // Trial 2: abort needs a reason.
  prepare(order[1]);
  rig.click(panel->startButton());
  rig.click(panel->attemptButton());
  pumpFor(1200);
  EXPECT_FALSE(panel->abortButton()->isEnabled());
  panel->abortReasonEdit()->setText("participant felt unwell");
  rig.click(panel->abortButton());

  // Trial 3: the time limit fails it by itself.
  prepare(order[2]);
  rig.click(panel->startButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->page() == StudyPanel::Page::kQuestionnaire; }, 20000))
      << panel->statusText().toStdString();

  const auto trials = panel->store()->trials();
  ASSERT_EQ(trials.size(), 3u);
  EXPECT_EQ(trials[0].mode, order[0]);
  EXPECT_EQ(trials[0].outcome, TrialOutcome::kSuccess);
  EXPECT_EQ(trials[0].attempts, 2);
  EXPECT_EQ(trials[0].notes, "dropped the peg once");
  EXPECT_GT(trials[0].duration_s, 1.4);
  EXPECT_EQ(trials[1].outcome, TrialOutcome::kAbort);
  EXPECT_EQ(trials[1].abort_reason, "participant felt unwell");
  EXPECT_EQ(trials[1].attempts, 1);
  EXPECT_EQ(trials[2].outcome, TrialOutcome::kTimeout);
  EXPECT_DOUBLE_EQ(trials[2].duration_s, limit_s);
  // Each trial's telemetry is kept with it: the operator's head poses, the head loop, and the
  // indicator the operator saw in the headset while it ran.
  for (const auto& t : trials) {
    const auto batches = panel->store()->telemetry(t.id);
    const auto decoded = study::decodeTrialTelemetry(batches, *study::utcNs(t.started_utc));
    // One head sample per XR display frame: the offscreen XR app under ASan beside other tests
    // showed exactly 20 in the 1.2 s trial on CI, so the counts ask only for a few frames (≥ 4
    // Hz) and the samples' span below says they cover the trial.
    EXPECT_GE(decoded.head.size(), 5u) << "trial " << t.order_index;
    EXPECT_GT(decoded.robot.size(), 50u) << "trial " << t.order_index;
    EXPECT_GE(framesWithIndicator(batches), 5u) << "trial " << t.order_index;
    ASSERT_FALSE(decoded.head.empty());
    EXPECT_GT(decoded.head.front().t_s, -1.0);  // samples fall inside the trial, on one clock
    EXPECT_LT(decoded.head.back().t_s, t.duration_s + 1.0);
    EXPECT_LT(decoded.head.front().t_s, 1.0);  // …and from its start to its end
    EXPECT_GT(decoded.head.back().t_s, t.duration_s - 1.0);
    double x_min = 1e9, x_max = -1e9;
    for (const study::HeadSample& h : decoded.head) {
      EXPECT_NEAR(h.y, 1.6, 1e-6);  // the scripted operator stands at 1.6 m
      x_min = std::min(x_min, h.x), x_max = std::max(x_max, h.x);
    }
    EXPECT_LE(x_max - x_min, 0.1 + 1e-6);  // and steps 10 cm sideways at most
  }
  // After the trials, the headset shows no indicator any more.
  EXPECT_TRUE(pumpUntil([&] { return rig.session->robotState() && !rig.session->robotState()->trial().running(); }));
  // The robot (--record-dir) recorded each trial under the participant, mode, the database's uid
  // (two studies' trial 1 never share a file) and the trial id.
  const QString uid = QString::fromStdString(panel->store()->uid());
  ASSERT_FALSE(uid.isEmpty());
  const auto fileOf = [&](const study::TrialRecord& t) {
    return QString("P05-%1-db%2-t%3.mcap").arg(QString::fromStdString(t.mode), uid).arg(t.id);
  };
  for (const study::TrialRecord& t : trials) {
    const QString file = rig.dir.filePath("recordings/" + fileOf(t));
    EXPECT_TRUE(QFileInfo::exists(file)) << file.toStdString();
    EXPECT_GT(QFileInfo(file).size(), 1000) << file.toStdString();
  }
  // …and the study database names each trial's file, as the robot confirmed it.
  for (const study::TrialRecord& t : panel->store()->trials())
    EXPECT_EQ(QFileInfo(QString::fromStdString(t.recording)).fileName().toStdString(), fileOf(t).toStdString())
        << "trial " << t.id;

  // The questionnaire pages, one per mode in the session's order, complete before save.
  for (int page = 0; page < 3; ++page) {
    ASSERT_EQ(panel->page(), StudyPanel::Page::kQuestionnaire);
    QuestionnairePage* q = panel->questionnaire();
    ASSERT_EQ(q->mode(), order[std::size_t(page)]);
    EXPECT_FALSE(q->saveButton()->isEnabled());
    const auto items = study::paperLikert().items;
    for (std::size_t i = 0; i + 1 < items.size(); ++i) ASSERT_TRUE(q->answer("paper_likert", items[i].key, 3));
    EXPECT_FALSE(q->saveButton()->isEnabled()) << "one item left";
    if (page == 0) shootStudy(rig, "study_questionnaire.png");
    answerPage(q, page);
    EXPECT_TRUE(q->saveButton()->isEnabled());
    q->saveButton()->click();
    pumpFor(50);
  }
  ASSERT_EQ(panel->page(), StudyPanel::Page::kDone);
  EXPECT_EQ(panel->store()->answers().size(), 21u);
  EXPECT_FALSE(panel->store()->sessions()[0].ended_utc.empty());
  panel->setReportDirectory(rig.dir.filePath("report"));
  panel->reportButton()->click();
  shootStudy(rig, "study_done.png");
  ASSERT_FALSE(panel->lastReport().isEmpty()) << panel->statusText().toStdString();
  for (const char* f : {"study-peg_trials.csv", "study-peg_answers.csv", "study-peg_table-i.md",
                        "study-peg_paper_likert.png", "study-peg_summary.json", "study.sqlite"})
    EXPECT_TRUE(QFileInfo::exists(rig.dir.filePath(QString("report/") + f))) << f;
  const QString head_png = rig.dir.filePath(QString("report/telemetry/study-peg_sub-P05_trial-1_mode-%1_id-%2_head.png")
                                                .arg(QString::fromStdString(order[0]))
                                                .arg(trials[0].id));
  EXPECT_TRUE(QFileInfo::exists(head_png)) << head_png.toStdString();
  QFile::remove(screenshotDir() + "/study_trial_head_motion.png");
  QFile::copy(head_png, screenshotDir() + "/study_trial_head_motion.png");
}

TEST(StudyWindow, KilledDuringATrialOrAQuestionnaireThenReopenedLosesNothing) {
  Rig rig(27950);
  rig.startRobot();
  rig.startXr(true);
  ASSERT_TRUE(pumpUntil([&] { return rig.connected(); }, 60000)) << rig.logs();
  const QString db = rig.dir.filePath("crash.sqlite");
  const QString study_file = writeStudy(rig.dir, 3.0);
  const auto runCrashing = [&](const QString& participant, const QString& when) {
    QProcess console;
    console.setProcessChannelMode(QProcess::MergedChannels);
    console.start(QString(TELESPHERE_BINARY_DIR "/tests/study_console_crash"),
                  {QString::number(rig.port), db, study_file, participant, when});
    EXPECT_TRUE(console.waitForFinished(120000));
    EXPECT_EQ(console.exitStatus(), QProcess::CrashExit) << console.readAll().toStdString();  // SIGKILL
  };
  runCrashing("P02", "questionnaire");
  runCrashing("P01", "trial");
  // The window the administrator opens next: a session per participant, nothing lost.
  StudyPanel* panel = rig.window->studyPanel();
  ASSERT_TRUE(panel->openStudy(study_file, db)) << panel->statusText().toStdString();
  ASSERT_EQ(panel->interruptedOnOpen().size(), 1u);
  shootStudy(rig, "study_reopened.png");
  EXPECT_TRUE(panel->statusText().contains("marked interrupted")) << panel->statusText().toStdString();
  const auto trials = panel->store()->trials();
  const study::TrialRecord& interrupted = trials.back();  // P01's session is the second
  EXPECT_EQ(interrupted.participant, "P01");
  EXPECT_EQ(interrupted.outcome, TrialOutcome::kInterrupted);
  EXPECT_EQ(interrupted.attempts, 2);
  EXPECT_EQ(interrupted.notes, "participant paused before the crash");
  EXPECT_GT(panel->store()->telemetry(interrupted.id).size(), 3u);  // committed once a second
  // P01 resumes at the interrupted trial, which is run again.
  panel->participantEdit()->setText("P01");
  panel->startSessionButton()->click();
  ASSERT_EQ(panel->page(), StudyPanel::Page::kTrials);
  EXPECT_EQ(panel->runner()->orderIndex(), 0);
  shootStudy(rig, "study_resumed.png");
  // Closing the window in the middle of that trial ends it as interrupted, with the reason.
  rig.click(panel->prepareButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->startButton()->isEnabled(); })) << panel->statusText().toStdString();
  rig.click(panel->startButton());
  rig.click(panel->attemptButton());
  pumpFor(300);
  rig.window->close();
  const auto after_close = panel->store()->trials();
  ASSERT_EQ(after_close.size(), trials.size() + 1);
  const study::TrialRecord& closed = after_close.back();
  EXPECT_EQ(closed.participant, "P01");
  EXPECT_EQ(closed.outcome, TrialOutcome::kInterrupted);
  EXPECT_EQ(closed.attempts, 1);
  EXPECT_EQ(closed.abort_reason, "the console window was closed during the trial");
  EXPECT_EQ(panel->page(), StudyPanel::Page::kParticipant);
  // P02 resumes on the questionnaire page it was on, with its three answers.
  panel->participantEdit()->setText("P02");
  panel->startSessionButton()->click();
  ASSERT_EQ(panel->page(), StudyPanel::Page::kQuestionnaire);
  EXPECT_EQ(panel->questionnaire()->mode(), panel->sessionRecord()->order[0]);
  EXPECT_EQ(panel->questionnaire()->answeredCount(), 3);
  EXPECT_FALSE(panel->questionnaire()->saveButton()->isEnabled());
  std::size_t p2_timeouts = 0;
  for (const auto& t : trials) p2_timeouts += t.participant == "P02" && t.outcome == TrialOutcome::kTimeout;
  EXPECT_EQ(p2_timeouts, 3u);
}

// Issue #30: the administrator changes the participant, or opens another study, while a mode
// switch is pending; the robot's reply and the XR app's timeout come afterwards. They must touch
// nothing of the trial workflow that is gone (under ASan, a write into it stops the test).
TEST(StudyWindow, ChangingTheParticipantOrTheStudyWhileAModeSwitchIsPendingIsSafe) {
  Rig rig(28310);
  rig.startRobot();  // no XR app: the switch waits for its confirmation, then times out
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robot().state() == supervision::PeerState::kConnected; }, 60000)) << rig.logs();
  StudyPanel* panel = rig.window->studyPanel();
  ASSERT_TRUE(panel->openStudy(writeStudy(rig.dir, 300), rig.dir.filePath("a.sqlite")));
  panel->participantEdit()->setText("P01");
  panel->startSessionButton()->click();
  ASSERT_EQ(panel->page(), StudyPanel::Page::kTrials);
  rig.click(panel->prepareButton());  // the request is out; its reply is handled on a later poll
  rig.click(panel->changeParticipantButton());
  EXPECT_EQ(panel->page(), StudyPanel::Page::kParticipant);
  pumpFor(int(StudyPanel::kModeSwitchTimeoutS * 1000) + 1500);  // the reply, then the timeout
  EXPECT_EQ(panel->page(), StudyPanel::Page::kParticipant);
  EXPECT_EQ(panel->runner(), nullptr);

  panel->participantEdit()->setText("P02");
  panel->startSessionButton()->click();
  ASSERT_EQ(panel->page(), StudyPanel::Page::kTrials);
  rig.click(panel->prepareButton());
  ASSERT_TRUE(panel->openStudy(writeStudy(rig.dir, 300), rig.dir.filePath("b.sqlite")));
  pumpFor(int(StudyPanel::kModeSwitchTimeoutS * 1000) + 1500);
  EXPECT_EQ(panel->page(), StudyPanel::Page::kParticipant);
  EXPECT_TRUE(panel->store()->trials().empty());
}

// Issue #30: the robot restarts during a trial. The new robot gets the trial indicator again and
// records a second part; the trial's row names both files and says what happened.
TEST(StudyWindow, ARobotRestartedMidTrialGetsTheIndicatorAndRecordsAgain) {
  Rig rig(28320);
  rig.startRobot();
  rig.startXr(true);
  ASSERT_TRUE(pumpUntil([&] { return rig.connected(); }, 60000)) << rig.logs();
  StudyPanel* panel = rig.window->studyPanel();
  ASSERT_TRUE(panel->openStudy(writeStudy(rig.dir, 300), rig.dir.filePath("restart.sqlite")));
  panel->participantEdit()->setText("P03");
  panel->startSessionButton()->click();
  rig.click(panel->prepareButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->startButton()->isEnabled(); })) << panel->statusText().toStdString();
  rig.click(panel->startButton());
  const auto row = [&] { return panel->store()->trials().back(); };
  ASSERT_TRUE(pumpUntil([&] { return !row().recording.empty(); })) << panel->statusText().toStdString();
  const std::string first = row().recording;
  EXPECT_NE(first.find("P03-"), std::string::npos) << first;
  EXPECT_NE(first.find("-db" + panel->store()->uid() + "-t"), std::string::npos) << first;

  rig.robot->stop();
  rig.startRobot();  // a new process on the same port and record folder
  ASSERT_TRUE(pumpUntil([&] { return row().recording.find("-part2") != std::string::npos; }, 60000))
      << row().recording << "\n" << row().recording_note << "\n" << rig.logs();
  EXPECT_NE(row().recording_note.find("the robot restarted"), std::string::npos) << row().recording_note;
  EXPECT_TRUE(panel->statusText().contains("recording part 2")) << panel->statusText().toStdString();
  rig.click(panel->successButton());
  const study::TrialRecord done = row();
  EXPECT_EQ(done.outcome, TrialOutcome::kSuccess);
  // Both parts are on disk (the robot names them with its record folder).
  const QString files = QString::fromStdString(done.recording);
  for (const QString& file : files.split("; ")) EXPECT_TRUE(QFileInfo::exists(file)) << file.toStdString();
  shootStudy(rig, "study_robot_restarted.png");
}

}  // namespace
}  // namespace telesphere::console
