// SPDX-License-Identifier: MIT
/// @brief The capacity of a bottleneck over time: piecewise constant, from a start rate and steps
///        (`--rate-mbit 50`, `--rate-steps "10:20,20:100"`) or a sawtooth made of small steps.
///        Answers when a packet that starts serialising at t finishes, integrating the rate over
///        the steps it spans. Times in ns from the start of the run, rates in bit/s; a rate of 0
///        is a link that carries nothing until the next step.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::bench::impairment {

struct RateStep {
  std::int64_t from_ns = 0;  ///< the rate holds from here until the next step
  double bits_per_s = 0;     ///< ≥ 0; +inf for no limit
};

class RateTrace {
 public:
  /// No limit: every packet is serialised in no time.
  RateTrace();
  /// One rate for the whole run.
  static RateTrace constant(double bits_per_s);
  /// A start rate at t = 0, then steps; steps must be in strictly increasing time, rates ≥ 0.
  /// Nothing (and the reason in *error) on a bad step.
  static std::optional<RateTrace> steps(double start_bits_per_s, std::vector<RateStep> later,
                                        std::string* error);
  /// Linear ramps from low to high over period_ns, then back to low at once, for duration_ns,
  /// approximated by steps every step_ns (the sawtooth of a competing flow's sending window).
  static RateTrace sawtooth(double low_bits_per_s, double high_bits_per_s, std::int64_t period_ns,
                            std::int64_t step_ns, std::int64_t duration_ns);
  /// "T:M,T:M,…": seconds from the start, Mbit/s (the benchmark's --rate-steps), after a start
  /// rate. Nothing, with "rate step 2 ('x:5'): …" in *error, on a malformed or unordered step.
  static std::optional<RateTrace> parseSteps(double start_bits_per_s, const std::string& text,
                                             std::string* error);

  /// The rate in force at t_ns (the last step at or before it).
  double bitsPerSecondAt(std::int64_t t_ns) const;
  /// When `bits` that start serialising at start_ns have all left: the rate integrated over the
  /// steps from start_ns on. INT64_MAX when the trace ends at rate 0 before they are through.
  std::int64_t serialisedBy(std::int64_t start_ns, double bits) const;

  const std::vector<RateStep>& rateSteps() const { return steps_; }

 private:
  std::vector<RateStep> steps_;  ///< first at 0
};

}  // namespace telesphere::bench::impairment
