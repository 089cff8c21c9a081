// SPDX-License-Identifier: MIT
/// @brief The time source of the robot side: a steady clock in nanoseconds, behind an interface
///        so that tests and benchmarks drive time themselves (SimClock, robot/clock/sim_clock.h).
#pragma once

#include <cstdint>

#include "robot/link/link_endpoints.h"

namespace telesphere::robot::clock {

class Clock {
 public:
  virtual ~Clock() = default;
  /// Now, in ns on a steady (monotonic) clock; never decreases.
  virtual std::int64_t nowNs() const = 0;
};

/// The link's steady clock (link::linkNowNs): robot-side stamps and link stamps are one clock.
class SteadyClock final : public Clock {
 public:
  std::int64_t nowNs() const override { return link::linkNowNs(); }
};

}  // namespace telesphere::robot::clock
