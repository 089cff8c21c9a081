// SPDX-License-Identifier: MIT
/// @brief Waiting in tests for something another thread or process does (a message over the
///        link, a decoded frame): polls a condition every millisecond up to a limit.
#pragma once

#include <chrono>
#include <thread>

namespace telesphere::test {

/// Polls `condition` every millisecond for up to `limit`; true when it came true.
template <typename F>
bool eventually(F condition, std::chrono::milliseconds limit = std::chrono::milliseconds(10000)) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return condition();
}

}  // namespace telesphere::test
