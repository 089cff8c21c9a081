// SPDX-License-Identifier: MIT
/// @brief The relays' clock: the steady clock in ns.
#pragma once

#include <chrono>
#include <cstdint>

namespace telesphere::bench::impairment {

inline std::int64_t steadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace telesphere::bench::impairment
