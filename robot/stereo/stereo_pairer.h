// SPDX-License-Identifier: MIT
/// @brief Left and right camera frames paired by capture timestamp (DESIGN.md §4): the nearest
///        frame of the other camera within a tolerance, never one further away. With a hardware
///        trigger both cameras stamp the same instant (and, optionally, the same sequence
///        number); free-running cameras pair with the nearest frame within the tolerance.
///
/// Rule (StereoPairer): a frame arriving on one side pairs at once with the nearest waiting
/// frame of the other side whose capture time is within `tolerance_ns` (and, with
/// `match_sequence`, whose sequence number is equal; ties go to the older frame); otherwise it
/// waits. Hence no two waiting frames of opposite sides are ever within the tolerance of each
/// other, and no pair ever has |Δt| > tolerance_ns. A waiting frame is dropped when the other
/// side's newest frame is later than its capture time + tolerance_ns + reorder_ns (no partner
/// can come any more), when more than max_waiting frames wait on its side (the oldest goes), or
/// at flush(). Pairs are made as soon as they exist (no waiting for a possibly better partner:
/// the lowest latency); with a tolerance below half of both frame periods each frame has at
/// most one candidate, and the pairs are then the same for any interleaving of arrivals.
/// Frames may arrive in any interleaving of the two sides; a side's own frames may also arrive
/// out of order by up to reorder_ns.
///
/// StereoPairSource runs the pairer on two CameraSources, one puller thread per camera.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "robot/cameras/camera_side.h"
#include "robot/cameras/camera_source.h"

namespace telesphere::robot::stereo {


/// A left and a right frame captured within the tolerance.
struct StereoFrame {
  cameras::CameraFrame left;
  cameras::CameraFrame right;
  /// right.capture_ns − left.capture_ns.
  std::int64_t skewNs() const { return right.capture_ns - left.capture_ns; }
};

struct StereoPairerOptions {
  std::int64_t tolerance_ns = 2'000'000;  ///< the largest |Δt| of a pair (≥ 0)
  bool match_sequence = false;            ///< hardware trigger: also require equal sequence numbers
  std::int64_t reorder_ns = 0;            ///< how late a side's own frames may arrive (≥ 0)
  std::size_t max_waiting = 16;           ///< per side (≥ 1)
};

/// Frames of one side dropped unpaired, by reason.
struct StereoDrops {
  std::uint64_t no_partner = 0;  ///< the other side moved on without a frame within tolerance
  std::uint64_t overflow = 0;    ///< too many frames waiting on this side
  std::uint64_t flushed = 0;     ///< still waiting at flush()
  std::uint64_t total() const { return no_partner + overflow + flushed; }
};

struct StereoPairerStats {
  std::uint64_t pairs = 0;
  std::array<StereoDrops, 2> dropped;  ///< [left, right]
  std::int64_t max_abs_skew_ns = 0;    ///< over all pairs made
};

/// The pairing rule above; thread-safe (one mutex), so two puller threads may feed it.
class StereoPairer {
 public:
  explicit StereoPairer(StereoPairerOptions options = {});

  /// Adds a frame of `side`; the pair it completes, if any.
  std::optional<StereoFrame> push(cameras::CameraSide side, cameras::CameraFrame frame);
  /// Drops every waiting frame (end of stream), counted as flushed.
  void flush();
  StereoPairerStats stats() const;
  /// Frames waiting on `side`.
  std::size_t waiting(cameras::CameraSide side) const;
  const StereoPairerOptions& options() const { return options_; }

 private:
  void evictLocked();

  StereoPairerOptions options_;
  mutable std::mutex mutex_;
  std::array<std::deque<cameras::CameraFrame>, 2> waiting_;  ///< each sorted by capture_ns
  std::array<std::optional<std::int64_t>, 2> newest_ns_;
  StereoPairerStats stats_;
};

/// Pairs two running CameraSources: one thread per camera pulls frames into a StereoPairer;
/// completed pairs wait (at most `queue_depth`, the oldest dropped) for nextPair(). The cameras
/// must outlive this object; starting and stopping them is the caller's job.
class StereoPairSource {
 public:
  StereoPairSource(cameras::CameraSource& left, cameras::CameraSource& right, StereoPairerOptions options = {},
                   std::size_t queue_depth = 2);
  ~StereoPairSource();
  StereoPairSource(const StereoPairSource&) = delete;
  StereoPairSource& operator=(const StereoPairSource&) = delete;

  /// Starts the puller threads (idempotent).
  void start();
  /// Stops the puller threads (within one camera poll, ≤ 20 ms) and wakes nextPair().
  void stop();
  /// The next pair, waiting up to `timeout`; nothing on timeout or when stopped.
  std::optional<StereoFrame> nextPair(std::chrono::milliseconds timeout);
  StereoPairerStats stats() const { return pairer_.stats(); }
  /// Pairs dropped from the full queue because nextPair() was not called in time.
  std::uint64_t pairsDropped() const;

 private:
  void pull(cameras::CameraSide side, cameras::CameraSource& camera);

  cameras::CameraSource& left_;
  cameras::CameraSource& right_;
  StereoPairer pairer_;
  std::size_t queue_depth_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<StereoFrame> pairs_;
  std::uint64_t pairs_dropped_ = 0;
  std::atomic<bool> running_{false};
  std::array<std::thread, 2> threads_;
};

}  // namespace telesphere::robot::stereo
