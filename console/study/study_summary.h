// SPDX-License-Identifier: MIT
/// @brief The study's summary figures (paper §IV-B): Table I — per mode the successes k/n and the
///        mean and sample standard deviation of the completion time of the successful trials —
///        and the box-plot statistics of every questionnaire item per mode: median and quartiles
///        (linear interpolation between order statistics, R type 7), whiskers to the most extreme
///        answers within the fences Q1 − 1.5·IQR and Q3 + 1.5·IQR, the answers beyond them as
///        outliers, and the mean. n counts each participant's trial position once, by how it
///        finally ended: a trial interrupted (the console went away) and run again counts as the
///        run that ended; one interrupted and never run again counts as interrupted (it did not
///        succeed), as aborted trials do; trials still running are not counted. `interrupted`
///        says how many interrupted runs there were (re-run or not).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "console/study/study_store.h"

namespace telesphere::console::study {

struct ModeSummary {
  std::string mode;
  int successes = 0, trials = 0;
  int timeouts = 0, fails = 0, aborts = 0, interrupted = 0;
  double mean_completion_s = 0, sd_completion_s = 0;  ///< over successes (NaN when < 1 / < 2)
};

struct BoxStats {
  int n = 0;
  double median = 0, q1 = 0, q3 = 0, lower_whisker = 0, upper_whisker = 0, mean = 0;
  std::vector<double> outliers;
};

/// Box-plot statistics of `values` (not empty).
BoxStats boxStats(std::vector<double> values);

struct StudySummary {
  std::vector<ModeSummary> table;  ///< in `modes` order
  /// (instrument, item) → mode → statistics
  std::map<std::pair<std::string, std::string>, std::map<std::string, BoxStats>> items;
};

StudySummary summarise(const std::vector<std::string>& modes, const std::vector<TrialRecord>& trials,
                       const std::vector<AnswerRecord>& answers);

/// Every figure of the summary (summary.json).
nlohmann::json toJson(const StudySummary& summary);

}  // namespace telesphere::console::study
