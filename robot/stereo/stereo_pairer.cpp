// SPDX-License-Identifier: MIT
/// @brief Stereo pairing by capture timestamp (see stereo_pairer.h).
#include "robot/stereo/stereo_pairer.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <utility>

#include "calib/debug_assert.h"

namespace telesphere::robot::stereo {

StereoPairer::StereoPairer(StereoPairerOptions options) : options_(options) {
  TS_ASSERT(options_.tolerance_ns >= 0, options_.tolerance_ns);
  TS_ASSERT(options_.reorder_ns >= 0, options_.reorder_ns);
  options_.max_waiting = std::max<std::size_t>(1, options_.max_waiting);
}

std::optional<StereoFrame> StereoPairer::push(cameras::CameraSide side, cameras::CameraFrame frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto s = static_cast<std::size_t>(side), o = 1 - s;
  newest_ns_[s] = std::max(newest_ns_[s].value_or(std::numeric_limits<std::int64_t>::min()),
                           frame.capture_ns);
  // The nearest waiting frame of the other side within the tolerance (the older one on a tie).
  std::deque<cameras::CameraFrame>& others = waiting_[o];
  std::optional<std::size_t> best;
  std::int64_t best_abs_ns = std::numeric_limits<std::int64_t>::max();
  for (std::size_t i = 0; i < others.size(); ++i) {
    const std::int64_t abs_ns = std::abs(others[i].capture_ns - frame.capture_ns);
    if (abs_ns > options_.tolerance_ns || abs_ns >= best_abs_ns) continue;
    if (options_.match_sequence && others[i].sequence != frame.sequence) continue;
    best = i;
    best_abs_ns = abs_ns;
  }
  std::optional<StereoFrame> pair;
  if (best) {
    cameras::CameraFrame partner = std::move(others[*best]);
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(*best));
    pair.emplace();
    pair->left = side == cameras::CameraSide::kLeft ? std::move(frame) : std::move(partner);
    pair->right = side == cameras::CameraSide::kLeft ? std::move(partner) : std::move(frame);
    ++stats_.pairs;
    stats_.max_abs_skew_ns = std::max(stats_.max_abs_skew_ns, std::abs(pair->skewNs()));
  } else {
    std::deque<cameras::CameraFrame>& mine = waiting_[s];
    const auto at = std::upper_bound(mine.begin(), mine.end(), frame.capture_ns,
                                     [](std::int64_t t, const cameras::CameraFrame& f) { return t < f.capture_ns; });
    mine.insert(at, std::move(frame));
    while (mine.size() > options_.max_waiting) {
      mine.pop_front();
      ++stats_.dropped[s].overflow;
    }
  }
  evictLocked();
  return pair;
}

void StereoPairer::evictLocked() {
  for (std::size_t s = 0; s < 2; ++s) {
    const auto& newest_other = newest_ns_[1 - s];
    if (!newest_other) continue;
    // Frames of the other side still to come are later than newest − reorder.
    while (!waiting_[s].empty() &&
           *newest_other - waiting_[s].front().capture_ns > options_.tolerance_ns + options_.reorder_ns) {
      waiting_[s].pop_front();
      ++stats_.dropped[s].no_partner;
    }
  }
}

void StereoPairer::flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t s = 0; s < 2; ++s) {
    stats_.dropped[s].flushed += waiting_[s].size();
    waiting_[s].clear();
  }
}

StereoPairerStats StereoPairer::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

std::size_t StereoPairer::waiting(cameras::CameraSide side) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return waiting_[static_cast<std::size_t>(side)].size();
}

StereoPairSource::StereoPairSource(cameras::CameraSource& left, cameras::CameraSource& right, StereoPairerOptions options,
                                   std::size_t queue_depth)
    : left_(left), right_(right), pairer_(options), queue_depth_(std::max<std::size_t>(1, queue_depth)) {}

StereoPairSource::~StereoPairSource() { stop(); }

void StereoPairSource::start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (running_.load()) return;
  running_.store(true);
  threads_[0] = std::thread([this] { pull(cameras::CameraSide::kLeft, left_); });
  threads_[1] = std::thread([this] { pull(cameras::CameraSide::kRight, right_); });
}

void StereoPairSource::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    running_.store(false);
  }
  ready_.notify_all();
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
}

void StereoPairSource::pull(cameras::CameraSide side, cameras::CameraSource& camera) {
  constexpr std::chrono::milliseconds kPoll(20);
  while (running_.load()) {
    const auto asked = std::chrono::steady_clock::now();
    std::optional<cameras::CameraFrame> frame = camera.nextFrame(kPoll);
    if (!frame) {
      // A stopped camera answers at once: do not spin on it.
      if (std::chrono::steady_clock::now() - asked < std::chrono::milliseconds(1)) {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait_for(lock, kPoll, [this] { return !running_.load(); });
      }
      continue;
    }
    std::optional<StereoFrame> pair = pairer_.push(side, std::move(*frame));
    if (!pair) continue;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pairs_.push_back(std::move(*pair));
      while (pairs_.size() > queue_depth_) {
        pairs_.pop_front();
        ++pairs_dropped_;
      }
    }
    ready_.notify_all();
  }
}

std::optional<StereoFrame> StereoPairSource::nextPair(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait_for(lock, timeout, [this] { return !running_.load() || !pairs_.empty(); });
  if (!running_.load() || pairs_.empty()) return std::nullopt;
  StereoFrame pair = std::move(pairs_.front());
  pairs_.pop_front();
  return pair;
}

std::uint64_t StereoPairSource::pairsDropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pairs_dropped_;
}

}  // namespace telesphere::robot::stereo
