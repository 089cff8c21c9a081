// SPDX-License-Identifier: MIT
/// @brief A rate limit: `rate_per_s` on average, `burst` at once (DESIGN.md §10: handshakes and
///        control requests per peer). Not thread-safe; one per peer, owned by one thread.
#pragma once

#include <algorithm>
#include <cstdint>

namespace telesphere::link::trust {

class TokenBucket {
 public:
  TokenBucket(double rate_per_s, double burst) : rate_per_s_(rate_per_s), burst_(burst), tokens_(burst) {}

  /// Takes one token at `t_ns` (a steady clock); false when none is left.
  bool take(std::int64_t t_ns) {
    if (last_ns_ != 0 && t_ns > last_ns_) tokens_ = std::min(burst_, tokens_ + double(t_ns - last_ns_) * 1e-9 * rate_per_s_);
    last_ns_ = std::max(last_ns_, t_ns);
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }

 private:
  double rate_per_s_, burst_, tokens_;
  std::int64_t last_ns_ = 0;
};

}  // namespace telesphere::link::trust
