// SPDX-License-Identifier: MIT
/// @brief Who a key belongs to on the link (DESIGN.md §10): the robot itself, the operator (head
///        targets, its own view), the supervisor (every control) or a viewer (telemetry and
///        previews only). Written into every key file, so the robot knows what a peer may do.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace telesphere::link::trust {

enum class LinkRole { kRobot, kOperator, kSupervisor, kViewer };

/// "robot", "operator", "supervisor", "viewer".
std::string_view linkRoleName(LinkRole role);
/// The role named `name` (exactly as linkRoleName writes it); nothing for anything else.
std::optional<LinkRole> parseLinkRole(std::string_view name);
/// "a robot", "an operator", "a supervisor", "a viewer": for messages.
std::string linkRoleWithArticle(LinkRole role);
/// "robot|operator|supervisor|viewer", for messages and help texts.
std::string linkRoleChoices();

}  // namespace telesphere::link::trust
