// SPDX-License-Identifier: MIT
/// @brief A console that dies mid-study: opens the study database, starts a session and a trial,
///        records `attempts` attempts, optionally saves the first `answers` answers of a
///        questionnaire page, and then kills itself with SIGKILL (no destructor, no close: what
///        kill -9 or a crash leaves). test_study runs it and reopens the database.
/// Usage: study_crash_writer DB PARTICIPANT ATTEMPTS ANSWERS
#include <QCoreApplication>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "console/study/study_definition.h"
#include "console/study/study_store.h"
#include "console/study/trial_order.h"

int main(int argc, char** argv) {
  using namespace telesphere::console::study;
  if (argc != 5) return 2;
  QCoreApplication app(argc, argv);
  std::string error;
  auto store = StudyStore::open(argv[1], &error);
  if (!store) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 3;
  }
  StudyDefinition study;
  study.questionnaires = {paperLikert()};
  const auto session = store->startSession(argv[2], 0, study, trialOrder(study, 0), &error);
  const auto trial = session ? store->startTrial(*session, 0, "full6d", study.time_limit_s, &error) : std::nullopt;
  if (!trial) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 4;
  }
  for (int i = 0; i < std::atoi(argv[3]); ++i)
    if (!store->addAttempt(*trial, &error)) return 5;
  const int answers = std::atoi(argv[4]);
  if (answers > 0) {  // the trial ended, the questionnaire page is half filled in
    if (!store->endTrial(*trial, TrialOutcome::kSuccess, 42.5, "", &error)) return 6;
    const auto items = paperLikert().items;
    for (int i = 0; i < answers && i < static_cast<int>(items.size()); ++i)
      if (!store->saveAnswer(*session, "full6d", "paper_likert", items[static_cast<std::size_t>(i)].key, 1 + i % 7,
                             &error))
        return 7;
  }
  std::raise(SIGKILL);
  return 0;
}
