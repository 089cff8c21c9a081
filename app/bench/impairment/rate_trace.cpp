// SPDX-License-Identifier: MIT
#include "app/bench/impairment/rate_trace.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace telesphere::bench::impairment {

RateTrace::RateTrace() : steps_{{0, std::numeric_limits<double>::infinity()}} {}

RateTrace RateTrace::constant(double bits_per_s) {
  RateTrace trace;
  trace.steps_ = {{0, bits_per_s > 0 ? bits_per_s : 0.0}};
  return trace;
}

std::optional<RateTrace> RateTrace::steps(double start_bits_per_s, std::vector<RateStep> later,
                                          std::string* error) {
  RateTrace trace = constant(start_bits_per_s);
  if (!(start_bits_per_s >= 0)) {
    if (error) *error = "the start rate must be ≥ 0 bit/s, not " + std::to_string(start_bits_per_s);
    return std::nullopt;
  }
  for (std::size_t i = 0; i < later.size(); ++i) {
    const RateStep& step = later[i];
    if (!(step.bits_per_s >= 0)) {
      if (error) *error = "rate step " + std::to_string(i + 1) + ": the rate must be ≥ 0 bit/s";
      return std::nullopt;
    }
    if (step.from_ns <= trace.steps_.back().from_ns) {
      if (error) *error = "rate step " + std::to_string(i + 1) + ": times must increase and be after 0";
      return std::nullopt;
    }
    trace.steps_.push_back(step);
  }
  return trace;
}

RateTrace RateTrace::sawtooth(double low_bits_per_s, double high_bits_per_s, std::int64_t period_ns,
                              std::int64_t step_ns, std::int64_t duration_ns) {
  RateTrace trace = constant(low_bits_per_s);
  if (period_ns <= 0 || step_ns <= 0) return trace;
  trace.steps_.clear();
  for (std::int64_t t = 0; t < std::max<std::int64_t>(duration_ns, 1); t += step_ns) {
    const double phase = static_cast<double>(t % period_ns) / static_cast<double>(period_ns);
    trace.steps_.push_back({t, std::max(0.0, low_bits_per_s + phase * (high_bits_per_s - low_bits_per_s))});
  }
  return trace;
}

std::optional<RateTrace> RateTrace::parseSteps(double start_bits_per_s, const std::string& text,
                                               std::string* error) {
  std::vector<RateStep> steps;
  std::stringstream list(text);
  std::string item;
  int index = 0;
  while (std::getline(list, item, ',')) {
    ++index;
    const auto colon = item.find(':');
    const std::string where = "rate step " + std::to_string(index) + " ('" + item + "'): ";
    if (colon == std::string::npos) {
      if (error) *error = where + "want seconds:Mbit/s";
      return std::nullopt;
    }
    try {
      std::size_t used_t = 0, used_r = 0;
      const std::string t_text = item.substr(0, colon), r_text = item.substr(colon + 1);
      const double t_s = std::stod(t_text, &used_t);
      const double rate_mbit = std::stod(r_text, &used_r);
      if (used_t != t_text.size() || used_r != r_text.size() || !std::isfinite(t_s) ||
          !std::isfinite(rate_mbit) || t_s <= 0 || rate_mbit < 0) {
        if (error) *error = where + "want seconds > 0 and Mbit/s ≥ 0";
        return std::nullopt;
      }
      steps.push_back({static_cast<std::int64_t>(std::llround(t_s * 1e9)), rate_mbit * 1e6});
    } catch (const std::exception&) {
      if (error) *error = where + "want seconds:Mbit/s";
      return std::nullopt;
    }
  }
  std::string why;
  auto trace = RateTrace::steps(start_bits_per_s, std::move(steps), &why);
  if (!trace && error) *error = why;
  return trace;
}

double RateTrace::bitsPerSecondAt(std::int64_t t_ns) const {
  double rate = steps_.front().bits_per_s;
  for (const RateStep& step : steps_) {
    if (step.from_ns > t_ns) break;
    rate = step.bits_per_s;
  }
  return rate;
}

std::int64_t RateTrace::serialisedBy(std::int64_t start_ns, double bits) const {
  if (bits <= 0) return start_ns;
  // The step in force at start_ns, then each later one until the bits are through.
  std::size_t i = 0;
  while (i + 1 < steps_.size() && steps_[i + 1].from_ns <= start_ns) ++i;
  double t_ns = static_cast<double>(start_ns);
  double left = bits;
  for (; i < steps_.size(); ++i) {
    const double rate = steps_[i].bits_per_s;
    const double end_ns = i + 1 < steps_.size() ? static_cast<double>(steps_[i + 1].from_ns)
                                                : std::numeric_limits<double>::infinity();
    if (std::isinf(rate)) return static_cast<std::int64_t>(t_ns);
    if (rate > 0) {
      const double need_ns = left * 1e9 / rate;
      if (t_ns + need_ns <= end_ns) return static_cast<std::int64_t>(std::ceil(t_ns + need_ns - 1e-6));
      left -= (end_ns - t_ns) * rate / 1e9;
    }
    t_ns = end_ns;
  }
  return std::numeric_limits<std::int64_t>::max();
}

}  // namespace telesphere::bench::impairment
