// SPDX-License-Identifier: MIT
/// @brief LinkRole names (see link_role.h).
#include "robot/link/trust/link_role.h"

#include <array>

namespace telesphere::link::trust {
namespace {

constexpr std::array<std::pair<LinkRole, std::string_view>, 4> kRoleNames{{{LinkRole::kRobot, "robot"},
                                                                            {LinkRole::kOperator, "operator"},
                                                                            {LinkRole::kSupervisor, "supervisor"},
                                                                            {LinkRole::kViewer, "viewer"}}};

}  // namespace

std::string_view linkRoleName(LinkRole role) {
  for (const auto& [r, name] : kRoleNames)
    if (r == role) return name;
  return "unknown";
}

std::optional<LinkRole> parseLinkRole(std::string_view name) {
  for (const auto& [r, n] : kRoleNames)
    if (n == name) return r;
  return std::nullopt;
}

std::string linkRoleChoices() {
  std::string out;
  for (const auto& [r, name] : kRoleNames) {
    if (!out.empty()) out += '|';
    out += name;
  }
  return out;
}

std::string linkRoleWithArticle(LinkRole role) {
  return (role == LinkRole::kOperator ? "an " : "a ") + std::string(linkRoleName(role));
}

}  // namespace telesphere::link::trust
