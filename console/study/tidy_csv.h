// SPDX-License-Identifier: MIT
/// @brief The study's tidy CSV, written for analysts and read back by `study import`:
///        `study-<name>_trials.csv`, one row per trial — participant, session, order_index, mode,
///        start_utc, end_utc, duration_s, success (0/1), outcome, attempts, time_limit_s,
///        abort_reason, notes, recording (the trial's session recordings; absent in older files),
///        recording_note (why it is not wholly recorded; absent in older files) —
///        and `study-<name>_answers.csv`, one row per answer — participant, mode, instrument,
///        item, value. RFC 4180 quoting.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "console/study/study_store.h"

namespace telesphere::console::study {

bool writeTrialsCsv(const std::string& path, const std::vector<TrialRecord>& trials, std::string* error);
bool writeAnswersCsv(const std::string& path, const std::vector<AnswerRecord>& answers, std::string* error);

/// Reads what the writers write (columns by header name, so their order may differ); nothing,
/// with "<path>:<line>: <what>", on a bad row.
std::optional<std::vector<TrialRecord>> readTrialsCsv(const std::string& path, std::string* error);
std::optional<std::vector<AnswerRecord>> readAnswersCsv(const std::string& path, std::string* error);

}  // namespace telesphere::console::study
