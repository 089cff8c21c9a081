// SPDX-License-Identifier: MIT
/// @brief Table I and the box-plot statistics (see study_summary.h).
#include "console/study/study_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace telesphere::console::study {
namespace {

double quantile7(const std::vector<double>& sorted, double p) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

BoxStats boxStats(std::vector<double> values) {
  BoxStats b;
  if (values.empty()) return b;
  std::sort(values.begin(), values.end());
  b.n = static_cast<int>(values.size());
  b.median = quantile7(values, 0.5);
  b.q1 = quantile7(values, 0.25);
  b.q3 = quantile7(values, 0.75);
  const double iqr = b.q3 - b.q1, low_fence = b.q1 - 1.5 * iqr, high_fence = b.q3 + 1.5 * iqr;
  b.lower_whisker = b.q1;
  b.upper_whisker = b.q3;
  double sum = 0;
  for (const double v : values) {
    sum += v;
    if (v < low_fence || v > high_fence) {
      b.outliers.push_back(v);
      continue;
    }
    b.lower_whisker = std::min(b.lower_whisker, v);
    b.upper_whisker = std::max(b.upper_whisker, v);
  }
  b.mean = sum / static_cast<double>(values.size());
  return b;
}

StudySummary summarise(const std::vector<std::string>& modes, const std::vector<TrialRecord>& trials,
                       const std::vector<AnswerRecord>& answers) {
  StudySummary s;
  for (const std::string& mode : modes) {
    ModeSummary m;
    m.mode = mode;
    std::vector<double> times;
    // Each (session, order position) once: its last ended run, an interruption only when nothing
    // ended after it (trials() comes by session, position, then id: later runs come later).
    std::map<std::pair<std::int64_t, int>, const TrialRecord*> position;
    for (const TrialRecord& t : trials) {
      if (t.mode != mode || t.outcome == TrialOutcome::kRunning) continue;
      if (t.outcome == TrialOutcome::kInterrupted) ++m.interrupted;
      const TrialRecord*& counted = position[{t.session_id, t.order_index}];
      if (counted == nullptr || counted->outcome == TrialOutcome::kInterrupted || t.outcome != TrialOutcome::kInterrupted)
        counted = &t;
    }
    for (const auto& [key, t] : position) {
      ++m.trials;
      switch (t->outcome) {
        case TrialOutcome::kSuccess: ++m.successes, times.push_back(t->duration_s); break;
        case TrialOutcome::kTimeout: ++m.timeouts; break;
        case TrialOutcome::kFail: ++m.fails; break;
        case TrialOutcome::kAbort: ++m.aborts; break;
        case TrialOutcome::kInterrupted:
        case TrialOutcome::kRunning: break;
      }
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    m.mean_completion_s = nan;
    m.sd_completion_s = nan;
    if (!times.empty()) {
      double sum = 0;
      for (double t : times) sum += t;
      m.mean_completion_s = sum / static_cast<double>(times.size());
      if (times.size() > 1) {
        double ss = 0;
        for (double t : times) ss += (t - m.mean_completion_s) * (t - m.mean_completion_s);
        m.sd_completion_s = std::sqrt(ss / static_cast<double>(times.size() - 1));
      }
    }
    s.table.push_back(m);
  }
  std::map<std::pair<std::string, std::string>, std::map<std::string, std::vector<double>>> values;
  for (const AnswerRecord& a : answers) values[{a.instrument, a.item}][a.mode].push_back(a.value);
  for (auto& [key, by_mode] : values)
    for (auto& [mode, v] : by_mode) s.items[key][mode] = boxStats(v);
  return s;
}

nlohmann::json toJson(const StudySummary& summary) {
  nlohmann::json table = nlohmann::json::array();
  for (const ModeSummary& m : summary.table)
    table.push_back({{"mode", m.mode},
                     {"successes", m.successes},
                     {"trials", m.trials},
                     {"timeouts", m.timeouts},
                     {"fails", m.fails},
                     {"aborts", m.aborts},
                     {"interrupted", m.interrupted},
                     {"completion_time_mean_s", number(m.mean_completion_s)},
                     {"completion_time_sd_s", number(m.sd_completion_s)}});
  nlohmann::json items = nlohmann::json::array();
  for (const auto& [key, by_mode] : summary.items) {
    nlohmann::json modes = nlohmann::json::object();
    for (const auto& [mode, b] : by_mode)
      modes[mode] = {{"n", b.n},           {"median", b.median},          {"q1", b.q1},
                     {"q3", b.q3},         {"lower_whisker", b.lower_whisker}, {"upper_whisker", b.upper_whisker},
                     {"mean", b.mean},     {"outliers", b.outliers}};
    items.push_back({{"instrument", key.first}, {"item", key.second}, {"modes", modes}});
  }
  return {{"table_i", table}, {"items", items},
          {"quartiles", "linear interpolation between order statistics (R type 7); whiskers to the most extreme "
                        "value within 1.5 IQR of the box"}};
}

}  // namespace telesphere::console::study
