// SPDX-License-Identifier: MIT
/// @brief Key pairs by libzmq (see link_key_pair.h).
#include "robot/link/trust/link_key_pair.h"

#include <zmq.h>

#include <array>

namespace telesphere::link::trust {

bool curveAvailable() { return zmq_has("curve") != 0; }

std::string checkKeyName(const std::string& name) {
  if (name.empty()) return "a key needs a name";
  if (name.size() > 64) return "the key name \"" + name.substr(0, 64) + "…\" is longer than 64 characters";
  if (name.front() == '.') return "the key name \"" + name + "\" starts with '.'";
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
                    c == '-';
    if (!ok) return "the key name \"" + name + "\" holds '" + std::string(1, c) + "' (use A–Z, a–z, 0–9, '.', '_', '-')";
  }
  return "";
}

std::optional<LinkKeyPair> generateKeyPair(const std::string& name, LinkRole role, std::string* error) {
  if (const std::string why = checkKeyName(name); !why.empty()) {
    *error = why;
    return std::nullopt;
  }
  if (!curveAvailable()) {
    *error = "this libzmq has no CURVE (built without libsodium): no keys can be made or used";
    return std::nullopt;
  }
  std::array<char, 41> public_z85{}, secret_z85{};
  if (zmq_curve_keypair(public_z85.data(), secret_z85.data()) != 0) {
    *error = std::string("zmq_curve_keypair: ") + zmq_strerror(zmq_errno());
    return std::nullopt;
  }
  return LinkKeyPair{{name, role, public_z85.data()}, secret_z85.data()};
}

std::optional<std::string> publicKeyOf(const std::string& secret_z85) {
  if (secret_z85.size() != 40 || !curveAvailable()) return std::nullopt;
  std::array<char, 41> public_z85{};
  if (zmq_curve_public(public_z85.data(), secret_z85.c_str()) != 0) return std::nullopt;
  return std::string(public_z85.data());
}

}  // namespace telesphere::link::trust
