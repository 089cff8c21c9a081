// SPDX-License-Identifier: MIT
/// @brief The allowed/ folder, read again when it changes (see allowed_keys.h).
#include "robot/link/trust/allowed_keys.h"

#include <algorithm>

#include "robot/link/trust/link_key_files.h"

namespace telesphere::link::trust {

namespace fs = std::filesystem;

AllowedKeys::AllowedKeys(fs::path dir) : dir_(std::move(dir)) { refresh(); }

std::string AllowedKeys::signature() const {
  // Names, sizes and modification times of every .pub: a copy, an edit, a removal or a rename
  // changes it. The folder's own state is part of it too (gone, unreadable).
  std::vector<std::string> entries;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir_, ec)) {
    if (entry.path().extension() != ".pub") continue;
    std::error_code ignored;
    const auto size = entry.file_size(ignored);
    const auto time = entry.last_write_time(ignored).time_since_epoch().count();
    entries.push_back(entry.path().filename().string() + "/" + std::to_string(size) + "/" + std::to_string(time));
  }
  if (ec) return "error: " + ec.message();
  std::sort(entries.begin(), entries.end());
  std::string text;
  for (const auto& e : entries) text += e + "\n";
  return text;
}

bool AllowedKeys::refresh() {
  const std::string now = signature();
  {
    std::lock_guard lock(mutex_);
    if (read_once_ && now == signature_) return false;
  }
  Snapshot fresh;
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir_, ec))
    if (entry.path().extension() == ".pub") files.push_back(entry.path());
  if (ec) fresh.errors.push_back(dir_.string() + ": " + ec.message());
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    std::string why;
    auto key = readPublicKey(file, &why);
    if (!key) {
      fresh.errors.push_back(why);
    } else if (key->role == LinkRole::kRobot) {
      fresh.errors.push_back(file.string() + ": a robot key; allowed/ holds the keys of operators, supervisors and viewers");
    } else if (std::any_of(fresh.keys.begin(), fresh.keys.end(),
                           [&](const LinkKey& k) { return k.public_z85 == key->public_z85; })) {
      fresh.errors.push_back(file.string() + ": the same key as another file here; only the first one counts");
    } else {
      fresh.keys.push_back(std::move(*key));
    }
  }
  std::lock_guard lock(mutex_);
  fresh.reloads = now_.reloads + (read_once_ ? 1 : 0);
  now_ = std::move(fresh);
  signature_ = now;
  read_once_ = true;
  return true;
}

std::optional<LinkKey> AllowedKeys::find(const std::string& public_z85) const {
  std::lock_guard lock(mutex_);
  for (const auto& key : now_.keys)
    if (key.public_z85 == public_z85) return key;
  return std::nullopt;
}

AllowedKeys::Snapshot AllowedKeys::snapshot() const {
  std::lock_guard lock(mutex_);
  return now_;
}

}  // namespace telesphere::link::trust
