// SPDX-License-Identifier: MIT
/// @brief Faults the supervisor must see (issue: a fault is a banner that stays until the
///        supervisor acknowledges it). Qt-free; time is passed in.
///
/// A condition (arm fault, robot gone, camera error, …) has a key. raise() while it holds: the
/// first time, or again after it was acknowledged and cleared, it opens a new fault; while one
/// is open it only updates its text. clear() when it stops holding: the fault stays on the
/// banner, marked cleared, until acknowledged. acknowledgeAll() takes everything off the banner;
/// a condition that still holds does not come back until it has cleared and happened again.
/// One-off events (the robot restarted) are raise() + clear() at once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace telesphere::console::supervision {

struct Fault {
  std::string key;
  std::string text;
  std::int64_t first_ns = 0;    ///< when it was raised
  std::int64_t cleared_ns = 0;  ///< when the condition stopped (0: still holds)
  int times = 1;                ///< raised again while on the banner
  bool acknowledged = false;
};

class FaultLog {
 public:
  static constexpr std::size_t kHistory = 500;

  void raise(const std::string& key, const std::string& text, std::int64_t now_ns);
  void clear(const std::string& key, std::int64_t now_ns);
  void acknowledgeAll();

  /// The faults on the banner, oldest first.
  std::vector<Fault> unacknowledged() const;
  /// Everything raised (newest kHistory), oldest first.
  const std::deque<Fault>& history() const { return faults_; }
  /// Changes whenever the banner's content does.
  std::uint64_t version() const { return version_; }

 private:
  Fault* open(const std::string& key);  ///< the newest fault of `key` not cleared, or null

  std::deque<Fault> faults_;
  std::uint64_t version_ = 0;
};

}  // namespace telesphere::console::supervision
