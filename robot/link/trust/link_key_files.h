// SPDX-License-Identifier: MIT
/// @brief Key pairs on disk (DESIGN.md §10): DIR/NAME.pub (name, role, public key; give it to the
///        peers that should trust NAME) and DIR/NAME.secret (the same and the secret key, mode
///        0600: a secret key that the group or others may read is refused, with the path and the
///        fix). Small YAML files a person can read.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "robot/link/trust/link_key_pair.h"

namespace telesphere::link::trust {

struct KeyPairPaths {
  std::filesystem::path public_file, secret_file;
};

/// Writes `pair` into `dir` (made if missing): the secret file is written 0600 and renamed into
/// place, so it is never readable by others, not even for a moment. Refuses to replace an
/// existing key of that name unless `replace`. Nothing, with the reason, on failure.
std::optional<KeyPairPaths> writeKeyPair(const LinkKeyPair& pair, const std::filesystem::path& dir, bool replace,
                                         std::string* error);
/// Reads a public key file (or the public half of a secret key file); nothing, with the path and
/// what is wrong in it.
std::optional<LinkKey> readPublicKey(const std::filesystem::path& file, std::string* error);
/// Reads a secret key file: refused when the group or others may read it ("chmod 600 PATH"), or
/// when its public key is not the one its secret key makes.
std::optional<LinkKeyPair> readKeyPair(const std::filesystem::path& secret_file, std::string* error);

}  // namespace telesphere::link::trust
