// SPDX-License-Identifier: MIT
/// @brief DeviceClockMapping: maps a camera's hardware timestamps (ns, the camera's own clock) to
///        the host clock (steady ns) by an online linear fit to the lower envelope of
///        (hardware stamp, host arrival) pairs, with clock offset and drift as figures.
#pragma once

#include <cstdint>
#include <deque>

namespace telesphere::robot::clock {

struct DeviceClockMappingOptions {
  int window = 512;                              ///< pairs kept (45 Hz: ~11 s)
  double max_drift_ppm = 200.0;                  ///< |b − 1| bound; quartz clocks stay inside (±20..100)
  std::int64_t jump_threshold_ns = 50'000'000;   ///< a pair this far off the fit is a clock jump
  int late_pairs_for_reset = 5;                  ///< consecutive pairs this late reset the fit too
};

/// Hardware time → host time: t_host = a + b·t_hw, fitted over a sliding window of pairs
/// (t_hw_i, t_arrival_i), where t_arrival is the host time the frame was seen on the host.
///
/// Why the lower envelope: t_arrival_i = a + b·t_hw_i + d_min + e_i with e_i ≥ 0 (transfer,
/// interrupt and scheduling delays only ever add). A least-squares fit would carry the mean of e
/// (and its noise) into the offset; instead the line is pushed up against the pairs from below:
/// among lines with every pair on or above them, the one highest at the window's mean t_hw (the
/// linear programme  max Σ(a + b·t_hw_i)  s.t.  a + b·t_hw_i ≤ t_arrival_i). Its solution is the
/// edge of the pairs' lower convex hull (in t_hw, t_arrival − t_hw) that spans the mean, so the fit
/// rests on the fastest arrivals only; with exponential jitter of mean μ over n pairs the error
/// is of order μ/n, not μ. |b − 1| is bounded by max_drift_ppm (needed while the window is short).
///
/// What it estimates: the mapped time is the *earliest* arrival of a frame with that stamp: the
/// true clock offset plus the minimum delay d_min (stamp latch → host), which no passive method
/// can separate; the camera subtracts its known part (exposure, transfer) after the mapping.
///
/// Clock jumps: a pair whose hardware stamp does not increase, or that lies more than
/// jump_threshold_ns below the fit (earlier than possible), resets the fit and starts a new one;
/// late_pairs_for_reset consecutive pairs more than jump_threshold_ns above it (the camera's clock
/// went back less than one frame period) do too. A single late pair is left out of the fit.
/// Call reset() when the camera is re-opened (its clock may have restarted).
///
/// Not thread-safe; one owner (the camera's stream thread).
class DeviceClockMapping {
 public:
  enum class AddResult { kAdded, kLateSkipped, kReset };

  explicit DeviceClockMapping(DeviceClockMappingOptions options = {});

  /// Adds one pair (hardware stamp, host arrival), both ns; refits. kReset: the pair showed a
  /// clock jump and starts a fresh fit; kLateSkipped: left out as a late outlier.
  AddResult add(std::int64_t hw_ns, std::int64_t host_arrival_ns);

  /// True once a pair has been added since construction or the last reset.
  bool valid() const { return !pairs_.empty(); }

  /// t_host = a + b·t_hw for a hardware stamp (ns), in host ns. Precondition: valid().
  std::int64_t toHostNs(std::int64_t hw_ns) const;

  /// hw_to_host_offset_ns = t_host − t_hw at the newest pair's hardware time (ns), i.e. a in the
  /// fit written around that point; includes the minimum arrival delay d_min (see class comment).
  std::int64_t hwToHostOffsetNs() const;

  /// Drift of the camera clock against the host clock: (b − 1)·10⁶, ppm. Positive: the host
  /// clock runs faster than the camera's.
  double driftPpm() const { return slope_ * 1e6; }

  /// Pairs in the window.
  std::size_t size() const { return pairs_.size(); }

  /// Resets caused by clock jumps since construction (reset() calls are not counted).
  std::uint64_t jumps() const { return jumps_; }

  /// Forgets all pairs.
  void reset();

 private:
  struct Pair {
    std::int64_t hw_ns;
    std::int64_t host_ns;
  };
  void refit();

  DeviceClockMappingOptions options_;
  std::deque<Pair> pairs_;
  // Fit around the newest pair (ref): t_host = ref.host + (t_hw − ref.hw) + offset_ + slope_·(t_hw − ref.hw).
  Pair ref_{0, 0};
  double offset_ = 0;
  double slope_ = 0;
  int late_run_ = 0;
  std::uint64_t jumps_ = 0;
};

}  // namespace telesphere::robot::clock
