// SPDX-License-Identifier: MIT
/// @brief A program's identity on the link (DESIGN.md §10): a CURVE key pair (ZeroMQ's, made by
///        libzmq with libsodium; no cryptography of ours) with the name and role the supervisor
///        gave it. Keys are Z85 text, 40 characters each.
#pragma once

#include <optional>
#include <string>

#include "robot/link/trust/link_role.h"

namespace telesphere::link::trust {

/// What a public key file says: enough for a peer to trust its owner in a role.
struct LinkKey {
  std::string name;
  LinkRole role = LinkRole::kViewer;
  std::string public_z85;
};

struct LinkKeyPair {
  LinkKey key;
  std::string secret_z85;
};

/// Whether this libzmq can do CURVE (zmq_has("curve"): built with libsodium).
bool curveAvailable();
/// "" when `name` can name a key (1–64 of A–Z a–z 0–9 . _ -, not starting with '.'), else why not.
std::string checkKeyName(const std::string& name);
/// A new pair for `name` in `role`; nothing, with the reason, for a bad name or without CURVE.
std::optional<LinkKeyPair> generateKeyPair(const std::string& name, LinkRole role, std::string* error);
/// The public key that belongs to `secret_z85` (zmq_curve_public); nothing for one that is not a
/// 40-character Z85 key.
std::optional<std::string> publicKeyOf(const std::string& secret_z85);

}  // namespace telesphere::link::trust
