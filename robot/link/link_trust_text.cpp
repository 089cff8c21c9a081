// SPDX-License-Identifier: MIT
/// @brief trustSummary, refusalSummary (see link_trust_text.h).
#include "robot/link/link_trust_text.h"

namespace telesphere::link {

std::string trustSummary(const proto::LinkTrustHealth& trust) {
  if (trust.insecure())
    return "INSECURE LINK (--insecure): no keys, anyone who reaches the ports can watch and move the arm";
  std::string text = "keys (CURVE): " + std::to_string(trust.allowed_size()) + " allowed";
  if (trust.allowed_errors_size() > 0) text += ", " + std::to_string(trust.allowed_errors_size()) + " unreadable in allowed/";
  text += ", operator seat: " + (trust.operator_seat().empty() ? std::string("free") : trust.operator_seat());
  return text;
}

std::string refusalSummary(const proto::LinkTrustHealth& trust, int max_entries) {
  std::string text;
  int shown = 0;
  for (const auto& r : trust.refusals()) {
    if (shown++ == max_entries) break;
    if (!text.empty()) text += "; ";
    text += std::to_string(r.count()) + " refused: " + r.cause();
    if (!r.name().empty()) text += " (" + r.name() + ")";
    text += " from " + (r.peer().empty() ? std::string("an unnamed address") : r.peer());
  }
  if (!text.empty() && trust.refusals_size() > max_entries)
    text += "; " + std::to_string(trust.refused_total()) + " refused in all";
  return text;
}

}  // namespace telesphere::link
