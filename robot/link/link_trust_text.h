// SPDX-License-Identifier: MIT
/// @brief The robot's trust health as a person reads it (DESIGN.md §10), the same words in the
///        console's health view and in `telesphere-console status`.
#pragma once

#include <string>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link {

/// "keys (CURVE): 3 allowed, operator seat: alice" or "INSECURE LINK (--insecure): …".
std::string trustSummary(const proto::LinkTrustHealth& trust);
/// "2 refused: unknown key from 10.0.0.7; 1 refused: role, viewer bob from 10.0.0.9" (the most
/// recent first, at most `max_entries`); "" when nobody was refused.
std::string refusalSummary(const proto::LinkTrustHealth& trust, int max_entries = 3);

}  // namespace telesphere::link
