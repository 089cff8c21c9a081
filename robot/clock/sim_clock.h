// SPDX-License-Identifier: MIT
/// @brief A clock that only moves when told to: deterministic time for tests and benchmarks.
#pragma once

#include <atomic>
#include <cstdint>

#include "calib/debug_assert.h"
#include "robot/clock/clock.h"

namespace telesphere::robot::clock {

class SimClock final : public Clock {
 public:
  explicit SimClock(std::int64_t start_ns = 0) : now_ns_(start_ns) {}
  std::int64_t nowNs() const override { return now_ns_.load(std::memory_order_acquire); }
  /// Moves time forward by dt_ns ≥ 0.
  void advance(std::int64_t dt_ns) {
    TS_ASSERT(dt_ns >= 0, dt_ns);
    now_ns_.fetch_add(dt_ns, std::memory_order_acq_rel);
  }
  /// Sets time to t_ns ≥ now (a steady clock never goes back).
  void set(std::int64_t t_ns) {
    TS_ASSERT(t_ns >= nowNs(), t_ns, nowNs());
    now_ns_.store(t_ns, std::memory_order_release);
  }

 private:
  std::atomic<std::int64_t> now_ns_;
};

}  // namespace telesphere::robot::clock
