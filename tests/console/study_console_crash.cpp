// SPDX-License-Identifier: MIT
/// @brief A console that dies mid-study through its real widgets (offscreen): opens the study in
///        the Study panel, starts the participant's session, then either runs the first trial
///        (mode switched and confirmed by robot and XR app, timer started, two attempts, notes
///        typed, telemetry flushed) or all trials to their time limit and half a questionnaire
///        page, and kills itself with SIGKILL: what kill -9 or a crash leaves. study_window_test
///        runs it against a real robot and XR app and reopens the database in a new window.
/// Usage: study_console_crash PORT DB STUDY_JSON PARTICIPANT trial|questionnaire
#include <QApplication>
#include <QElapsedTimer>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QThread>
#include <csignal>
#include <cstdio>
#include <functional>

#include "console/widgets/console_session.h"
#include "console/widgets/console_window.h"
#include "console/widgets/questionnaire_page.h"
#include "console/widgets/study_panel.h"
#include "tests/console/event_pump.h"

namespace {

using telesphere::console::test_rig::pumpUntil;

int fail(const char* what, const telesphere::console::StudyPanel& panel) {
  std::fprintf(stderr, "study_console_crash: %s (%s)\n", what, panel.statusText().toUtf8().constData());
  return 10;
}

}  // namespace

int main(int argc, char** argv) {
  using telesphere::console::StudyPanel;
  if (argc != 6) return 2;
  qputenv("QT_QPA_PLATFORM", "offscreen");
  QApplication app(argc, argv);
  QApplication::setOrganizationName("telesphere-test");
  QApplication::setApplicationName("study_console_crash");
  telesphere::console::ConsoleSessionOptions options;
  options.endpoints.base_port = std::atoi(argv[1]);
  telesphere::console::ConsoleSession session(options);
  telesphere::console::ConsoleWindow window(session);
  window.show();
  StudyPanel& panel = *window.studyPanel();
  if (!panel.openStudy(argv[3], argv[2])) return fail("open", panel);
  panel.participantEdit()->setText(argv[4]);
  panel.startSessionButton()->click();
  if (panel.page() != StudyPanel::Page::kTrials) return fail("session", panel);
  const std::string when = argv[5];
  const auto runTrial = [&] {
    panel.prepareButton()->click();
    return pumpUntil([&] { return panel.startButton()->isEnabled(); }, 30000);
  };
  if (when == "trial") {
    if (!runTrial()) return fail("mode not confirmed", panel);
    panel.startButton()->click();
    panel.attemptButton()->click();
    panel.attemptButton()->click();
    panel.notesEdit()->setPlainText("participant paused before the crash");
    pumpUntil([] { return false; }, 1300);  // telemetry committed once (the time limit is 3 s)
  } else {
    while (panel.page() == StudyPanel::Page::kTrials) {
      if (!runTrial()) return fail("mode not confirmed", panel);
      panel.startButton()->click();
      if (!pumpUntil([&] { return !panel.successButton()->isEnabled(); }, 30000)) return fail("time limit", panel);
    }
    if (panel.page() != StudyPanel::Page::kQuestionnaire) return fail("no questionnaire", panel);
    const char* items[] = {"situational_awareness", "see_objects", "judge_depth"};
    for (int i = 0; i < 3; ++i)
      if (!panel.questionnaire()->answer("paper_likert", items[i], 2 + i)) return fail("answer", panel);
  }
  std::fflush(stdout);
  std::raise(SIGKILL);
  return 0;
}
