// SPDX-License-Identifier: MIT
/// @brief `telesphere-console study …` (see console_study_command.h).
#include "app/console_study_command.h"

#include <QApplication>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include "console/study/study_report.h"
#include "console/study/study_store.h"
#include "console/study/tidy_csv.h"

namespace telesphere::app {

CLI::App* addStudyCommand(CLI::App& app, StudyCommandOptions& o) {
  CLI::App* study = app.add_subcommand("study", "user studies: report and import (headless)");
  study->require_subcommand(1);
  CLI::App* report = study->add_subcommand("report", "write the tidy CSV, Table I, box plots, summary.json and a copy of the database");
  report->add_option("--db", o.db, "study database (SQLite)")->required()->check(CLI::ExistingFile);
  report->add_option("--out", o.out, "folder for the report")->required();
  CLI::App* import = study->add_subcommand("import", "load tidy CSV (the report's columns) into a study database");
  import->add_option("--db", o.db, "study database (SQLite; created if missing)")->required();
  import->add_option("--trials", o.trials, "trials CSV")->check(CLI::ExistingFile);
  import->add_option("--answers", o.answers, "answers CSV")->check(CLI::ExistingFile);
  import->add_option("--study", o.study, "study definition (JSON; default: the paper's study)")->check(CLI::ExistingFile);
  return study;
}

int runStudyCommand(const CLI::App& study, const StudyCommandOptions& o, int argc, char** argv) {
  const auto fail = [](const std::string& message) {
    std::cerr << "telesphere-console study: " << message << '\n';
    return 1;
  };
  if (!std::getenv("QT_QPA_PLATFORM")) setenv("QT_QPA_PLATFORM", "offscreen", 1);  // plots, no window
  QApplication app(argc, argv);
  std::string error;
  if (study.got_subcommand("report")) {
    // A report reads a snapshot and changes nothing: a console may be running a trial in it now.
    auto snapshot = console::study::StudyStore::openSnapshot(o.db, &error);
    if (!snapshot) return fail(error);
    for (const auto& t : snapshot->trials())
      if (t.outcome == console::study::TrialOutcome::kRunning)
        std::cerr << "telesphere-console study: trial " << t.id << " (" << t.participant << ", " << t.mode
                  << ") is running: listed as running, not counted\n";
    const auto written = console::study::writeStudyReport(*snapshot, o.out, &error);
    if (!written) return fail(error);
    for (const std::string& path : *written) std::cout << path << '\n';
    return 0;
  }
  auto store = console::study::StudyStore::open(o.db, &error);
  if (!store) return fail(error);
  for (const auto& t : store->interruptedOnOpen())
    std::cerr << "telesphere-console study: trial " << t.id << " (" << t.participant << ", " << t.mode
              << ") was still running: marked interrupted\n";
  console::study::StudyDefinition definition;
  if (!o.study.empty()) {
    std::ifstream in(o.study);
    std::stringstream text;
    text << in.rdbuf();
    const auto parsed = console::study::StudyDefinition::parse(text.str(), &error);
    if (!parsed) return fail(o.study + ": " + error);
    definition = *parsed;
  } else {
    definition.questionnaires = {console::study::paperLikert()};
  }
  if (o.trials.empty() && o.answers.empty()) return fail("import: give --trials and/or --answers");
  std::vector<console::study::TrialRecord> trials;
  std::vector<console::study::AnswerRecord> answers;
  if (!o.trials.empty()) {
    auto rows = console::study::readTrialsCsv(o.trials, &error);
    if (!rows) return fail(error);
    trials = std::move(*rows);
  }
  if (!o.answers.empty()) {
    auto rows = console::study::readAnswersCsv(o.answers, &error);
    if (!rows) return fail(error);
    answers = std::move(*rows);
  }
  if (!store->importRows(definition, trials, answers, &error)) return fail("import: " + error + " (nothing imported)");
  std::cout << "imported " << trials.size() << " trials and " << answers.size() << " answers into study "
            << definition.name << " of " << o.db << '\n';
  return 0;
}

}  // namespace telesphere::app
