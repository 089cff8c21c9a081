// SPDX-License-Identifier: MIT
/// @brief The time source of the robot side: a steady clock in nanoseconds, behind an interface
///        so that tests and benchmarks drive time themselves (SimClock, robot/sim_clock.h).
#pragma once

#include <chrono>
#include <cstdint>

namespace telesphere::robot {

class Clock {
 public:
  virtual ~Clock() = default;
  /// Now, in ns on a steady (monotonic) clock; never decreases.
  virtual std::int64_t nowNs() const = 0;
};

/// std::chrono::steady_clock in ns.
class SteadyClock final : public Clock {
 public:
  std::int64_t nowNs() const override {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};

}  // namespace telesphere::robot
