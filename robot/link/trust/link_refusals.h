// SPDX-License-Identifier: MIT
/// @brief Every peer the robot refused, counted by cause and peer (DESIGN.md §10): the console's
///        health view shows them ("2 refused: unknown key from 10.0.0.7"), the log says each new
///        cause and peer once and then at most once a minute, so a flood cannot fill the disk.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

namespace telesphere::link::trust {

struct LinkRefusalCount {
  std::string cause;   ///< "unknown key", "no key", "wrong robot key", "broken handshake", "role", "operator seat", "rate limit", "revoked key"
  std::string detail;  ///< the newest explanation
  std::string peer;    ///< address, "" where ZeroMQ does not tell it
  std::string name;    ///< key name where known
  std::uint64_t count = 0;
  std::int64_t last_t_ns = 0;
};

class LinkRefusals {
 public:
  /// At most this many (cause, peer, name) entries are kept; beyond, the least recent is folded
  /// into the total only, so a flood from many addresses cannot grow memory.
  static constexpr std::size_t kMaxEntries = 64;

  void count(const std::string& cause, const std::string& detail, const std::string& peer, const std::string& name,
             std::int64_t t_ns);
  /// The entries, most recent first.
  std::vector<LinkRefusalCount> snapshot() const;
  std::uint64_t total() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, std::string>, LinkRefusalCount> entries_;
  std::map<std::tuple<std::string, std::string, std::string>, std::int64_t> logged_ns_;
  std::uint64_t total_ = 0;
};

}  // namespace telesphere::link::trust
