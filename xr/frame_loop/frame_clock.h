// SPDX-License-Identifier: MIT
/// @brief The clock a PacedOutput paces display frames by: the steady clock (live: the link's
///        clock), or a simulated one on which waiting jumps to the due time at once and work takes
///        no time, so display times are exactly start + k · period whatever the machine's speed
///        (an offline replay renders the same frames run after run; tests need no sleeps).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <thread>

#include "robot/link/link_endpoints.h"

namespace telesphere::xr::frame_loop {

class FrameClock {
 public:
  virtual ~FrameClock() = default;
  virtual std::int64_t nowNs() = 0;
  /// Returns at t_ns (at once when that has passed).
  virtual void sleepUntilNs(std::int64_t t_ns) = 0;
};

/// std::chrono::steady_clock, ns since its epoch (the link's clock, link::linkNowNs).
class SteadyFrameClock final : public FrameClock {
 public:
  std::int64_t nowNs() override { return link::linkNowNs(); }
  void sleepUntilNs(std::int64_t t_ns) override {
    std::this_thread::sleep_until(Clock::time_point(std::chrono::duration_cast<Clock::duration>(std::chrono::nanoseconds(t_ns))));
  }

 private:
  using Clock = std::chrono::steady_clock;
};

/// Time moves only when waited on.
class SimulatedFrameClock final : public FrameClock {
 public:
  explicit SimulatedFrameClock(std::int64_t start_ns) : now_ns_(start_ns) {}
  std::int64_t nowNs() override { return now_ns_; }
  void sleepUntilNs(std::int64_t t_ns) override { now_ns_ = std::max(now_ns_, t_ns); }

 private:
  std::int64_t now_ns_;
};

}  // namespace telesphere::xr::frame_loop
