// SPDX-License-Identifier: MIT
/// @brief What a program proves and whom it trusts on the link (DESIGN.md §10), read from the
///        folder given with --keys DIR:
///          - the robot's DIR: its own pair (one NAME.secret with role robot, NAME.pub beside it)
///            and allowed/ with the .pub of every peer it lets in (role and name inside each; the
///            robot reads allowed/ again whenever it changes, see AllowedKeys);
///          - a client's DIR: its own pair (operator, supervisor or viewer) and the robot's .pub.
///        No credentials (a default LinkCredentials) means an insecure link: plain TCP that anyone
///        who reaches the ports may use. Programs allow that only with --insecure.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "robot/link/trust/link_key_pair.h"

namespace telesphere::link::trust {

struct LinkCredentials {
  std::optional<LinkKeyPair> own;       ///< none: insecure
  std::string robot_public_z85;         ///< a client's: the robot it talks to
  std::filesystem::path allowed_dir;    ///< the robot's: the peers it trusts

  bool secure() const { return own.has_value(); }
};

/// The robot's credentials from DIR; nothing, with what is missing and how to make it.
std::optional<LinkCredentials> loadRobotCredentials(const std::filesystem::path& dir, std::string* error);
/// A client's credentials from DIR, for a program that acts in one of `roles` (the console:
/// supervisor or viewer; the XR app: operator); nothing, with the reason.
std::optional<LinkCredentials> loadClientCredentials(const std::filesystem::path& dir,
                                                     std::initializer_list<LinkRole> roles, std::string* error);

}  // namespace telesphere::link::trust
