// SPDX-License-Identifier: MIT
/// @brief The peers the robot lets in: the .pub files in its allowed/ folder (DESIGN.md §10),
///        read again whenever a file there is added, removed or changed, so a supervisor adds or
///        revokes a key without restarting the robot. A file that cannot be read is skipped with
///        the reason (shown in the console's health view), never taken as "allow everyone".
#pragma once

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "robot/link/trust/link_key_pair.h"

namespace telesphere::link::trust {

class AllowedKeys {
 public:
  explicit AllowedKeys(std::filesystem::path dir);

  /// Reads the folder again if anything in it changed since the last read; true when it did.
  bool refresh();
  /// The key with this public key (Z85), if allowed now.
  std::optional<LinkKey> find(const std::string& public_z85) const;

  struct Snapshot {
    std::vector<LinkKey> keys;
    std::vector<std::string> errors;  ///< "allowed/x.pub: why"
    std::uint64_t reloads = 0;        ///< reads after the first
  };
  Snapshot snapshot() const;

 private:
  std::string signature() const;

  const std::filesystem::path dir_;
  mutable std::mutex mutex_;
  std::string signature_;
  bool read_once_ = false;
  Snapshot now_;
};

}  // namespace telesphere::link::trust
