// SPDX-License-Identifier: MIT
/// @brief Counting refusals (see link_refusals.h).
#include "robot/link/trust/link_refusals.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace telesphere::link::trust {

void LinkRefusals::count(const std::string& cause, const std::string& detail, const std::string& peer,
                         const std::string& name, std::int64_t t_ns) {
  constexpr std::int64_t kLogPeriodNs = 60'000'000'000;
  std::lock_guard lock(mutex_);
  ++total_;
  const auto key = std::make_tuple(cause, peer, name);
  auto& entry = entries_[key];
  if (entry.count == 0) {
    entry.cause = cause;
    entry.peer = peer;
    entry.name = name;
  }
  entry.detail = detail;
  ++entry.count;
  entry.last_t_ns = t_ns;
  auto logged = logged_ns_.find(key);
  if (logged == logged_ns_.end() || t_ns - logged->second >= kLogPeriodNs) {
    spdlog::warn("link: refused {}{}{}: {} ({} so far)", cause, peer.empty() ? "" : " from ", peer, detail,
                 entry.count);
    logged_ns_[key] = t_ns;
  }
  while (entries_.size() > kMaxEntries) {
    auto oldest = std::min_element(entries_.begin(), entries_.end(), [](const auto& a, const auto& b) {
      return a.second.last_t_ns < b.second.last_t_ns;
    });
    logged_ns_.erase(oldest->first);
    entries_.erase(oldest);
  }
}

std::vector<LinkRefusalCount> LinkRefusals::snapshot() const {
  std::lock_guard lock(mutex_);
  std::vector<LinkRefusalCount> out;
  out.reserve(entries_.size());
  for (const auto& [key, entry] : entries_) out.push_back(entry);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.last_t_ns > b.last_t_ns; });
  return out;
}

std::uint64_t LinkRefusals::total() const {
  std::lock_guard lock(mutex_);
  return total_;
}

}  // namespace telesphere::link::trust
