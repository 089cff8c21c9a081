// SPDX-License-Identifier: MIT
/// @brief The one operator seat (DESIGN.md §10): only the seated operator's head targets move the
///        arm. The first operator key to send one takes a free seat and keeps it, across its own
///        reconnects, until a supervisor hands the seat to another operator or frees it; any other
///        operator is refused with the seated one's name.
#pragma once

#include <mutex>
#include <optional>
#include <string>

namespace telesphere::link::trust {

class OperatorSeat {
 public:
  /// Seats `name` if the seat is free; nothing when `name` is seated (now), else the holder.
  std::optional<std::string> claim(const std::string& name) {
    std::lock_guard lock(mutex_);
    if (holder_.empty()) holder_ = name;
    if (holder_ == name) return std::nullopt;
    return holder_;
  }
  /// A supervisor seats `name` ("" frees the seat).
  void handOver(const std::string& name) {
    std::lock_guard lock(mutex_);
    holder_ = name;
  }
  std::string holder() const {
    std::lock_guard lock(mutex_);
    return holder_;
  }

 private:
  mutable std::mutex mutex_;
  std::string holder_;
};

}  // namespace telesphere::link::trust
