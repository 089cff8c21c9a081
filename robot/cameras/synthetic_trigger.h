// SPDX-License-Identifier: MIT
/// @brief The trigger line two synthetic cameras share, so that a stereo pair stays a pair when
///        rendering falls behind the frame rate.
///
/// Real stereo cameras are triggered together: both expose every tick, and a slow host loses
/// frames later, in queues. A synthetic camera that falls behind instead skips to the latest
/// tick reached when it finishes a frame; two of them doing that on their own pick different
/// ticks as soon as one finishes a frame in another period than the other, and then keep
/// picking different ticks (equal render times hold the offset): the pairer finds no partner for
/// seconds (seen: 20 s without a stereo still on a loaded 2-core machine under ASan). Sharing a
/// trigger, the camera that is ready first claims the tick it wants; a camera that has not yet
/// rendered the tick its partner claimed renders that one instead of skipping past it.
///
///   camera L ──tickFor(wanted, last)──▶ SyntheticTrigger ◀──tickFor(wanted, last)── camera R
///
/// The cameras sharing a trigger must have the same fps and phase (each camera's ticks are its
/// own k in phase + k·period; the trigger compares k).
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>

namespace telesphere::robot::cameras {

class SyntheticTrigger {
 public:
  /// The tick a camera renders next. `next`: the tick after the one it rendered last (at its
  /// start, the first tick at or after the start); `wanted` ≥ next: its own choice (`next`, or
  /// the latest tick read out by now when it fell behind). A tick a partner claimed in
  /// [next, wanted) wins; otherwise `wanted` is claimed. Thread-safe.
  std::int64_t tickFor(std::int64_t next, std::int64_t wanted) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (claimed_ && *claimed_ >= next && *claimed_ < wanted) {
      ++followed_;
      return *claimed_;
    }
    if (!claimed_ || wanted > *claimed_) claimed_ = wanted;
    return wanted;
  }

  /// Frames rendered at a partner's tick rather than the latest (the follower catching up).
  std::uint64_t followed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return followed_;
  }

 private:
  mutable std::mutex mutex_;
  std::optional<std::int64_t> claimed_;  ///< the newest tick any camera chose
  std::uint64_t followed_ = 0;
};

}  // namespace telesphere::robot::cameras
