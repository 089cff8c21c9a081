// SPDX-License-Identifier: MIT
/// @brief `telesphere-console study report|import`: the study administrator's headless commands.
///   study report --db FILE --out DIR        tidy CSV, Table I, box plots (PNG, PDF), summary.json,
///                                           a copy of the database (console/study/study_report.h)
///   study import --db FILE --trials trials.csv [--answers answers.csv] [--study study.json]
///                                           loads tidy CSV in the report's columns (paper forms typed
///                                           in later, another site's data), all or nothing
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace telesphere::app {

struct StudyCommandOptions {
  std::string db, out, trials, answers, study;
};

/// Adds `study` with its `report` and `import` subcommands to `app`.
CLI::App* addStudyCommand(CLI::App& app, StudyCommandOptions& options);
/// Runs the one given; exit code 0 ok, 1 bad arguments or files.
int runStudyCommand(const CLI::App& study, const StudyCommandOptions& options, int argc, char** argv);

}  // namespace telesphere::app
