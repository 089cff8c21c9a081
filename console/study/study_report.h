// SPDX-License-Identifier: MIT
/// @brief Everything the analyst gets from a study database (`telesphere-console study report`):
///        per study, the tidy CSV (tidy_csv.h), the paper's Table I (`study-<name>_table-i.md`
///        and `.csv`), the Likert box plots per instrument (`study-<name>_<instrument>.png` and
///        `.pdf`: median, quartiles, whiskers to the fences, outliers, mean marker, one box per
///        mode and item, as in the paper's figure), `study-<name>_summary.json` with every figure,
///        and a consistent copy of the SQLite file. Needs a QApplication (the plots).
#pragma once

#include <string>
#include <vector>

#include "console/study/study_store.h"
#include "console/study/study_summary.h"

namespace telesphere::console::study {

/// Writes the report of every study in `store` into `dir` (created); the files written, or
/// nothing with the reason.
std::optional<std::vector<std::string>> writeStudyReport(const StudyStore& store, const std::string& dir,
                                                         std::string* error);

/// The box plots of one instrument as PNG and PDF (`path_stem` + ".png" / ".pdf").
bool writeLikertPlots(const StudySummary& summary, const std::vector<std::string>& modes,
                      const std::string& instrument, const std::string& path_stem, std::string* error);

}  // namespace telesphere::console::study
