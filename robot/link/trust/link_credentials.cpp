// SPDX-License-Identifier: MIT
/// @brief Reading a program's --keys folder (see link_credentials.h).
#include "robot/link/trust/link_credentials.h"

#include <algorithm>
#include <vector>

#include "robot/link/trust/link_key_files.h"

namespace telesphere::link::trust {
namespace {

namespace fs = std::filesystem;

/// The files in `dir` ending in `extension`, sorted; nothing, with the reason, when `dir` cannot be read.
std::optional<std::vector<fs::path>> filesEnding(const fs::path& dir, const std::string& extension, std::string* error) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = dir.string() + ": no such folder (make one with: telesphere-keys generate --role ROLE --name NAME --out " +
             dir.string() + ")";
    return std::nullopt;
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_regular_file() && entry.path().extension() == extension) files.push_back(entry.path());
  if (ec) {
    *error = dir.string() + ": " + ec.message();
    return std::nullopt;
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string joined(const std::vector<fs::path>& files) {
  std::string text;
  for (const auto& f : files) text += (text.empty() ? "" : ", ") + f.filename().string();
  return text;
}

/// The one secret key in `dir`, in one of `roles`.
std::optional<LinkKeyPair> ownPair(const fs::path& dir, std::initializer_list<LinkRole> roles, std::string* error) {
  const auto secrets = filesEnding(dir, ".secret", error);
  if (!secrets) return std::nullopt;
  std::string role_names;
  for (LinkRole r : roles) role_names += (role_names.empty() ? "" : "|") + std::string(linkRoleName(r));
  if (secrets->empty()) {
    *error = dir.string() + ": no secret key here (make one with: telesphere-keys generate --role " + role_names +
             " --name NAME --out " + dir.string() + ")";
    return std::nullopt;
  }
  if (secrets->size() > 1) {
    *error = dir.string() + ": more than one secret key (" + joined(*secrets) + "): a program has one identity";
    return std::nullopt;
  }
  auto pair = readKeyPair(secrets->front(), error);
  if (!pair) return std::nullopt;
  if (std::find(roles.begin(), roles.end(), pair->key.role) == roles.end()) {
    *error = secrets->front().string() + ": a " + std::string(linkRoleName(pair->key.role)) +
             " key; this program needs a " + role_names + " key";
    return std::nullopt;
  }
  return pair;
}

}  // namespace

std::optional<LinkCredentials> loadRobotCredentials(const fs::path& dir, std::string* error) {
  LinkCredentials credentials;
  credentials.own = ownPair(dir, {LinkRole::kRobot}, error);
  if (!credentials.own) return std::nullopt;
  credentials.allowed_dir = dir / "allowed";
  std::error_code ec;
  if (!fs::is_directory(credentials.allowed_dir, ec)) {
    *error = credentials.allowed_dir.string() +
             ": no such folder: make it and put there the .pub file of every operator, supervisor and viewer "
             "the robot should let in";
    return std::nullopt;
  }
  return credentials;
}

std::optional<LinkCredentials> loadClientCredentials(const fs::path& dir, std::initializer_list<LinkRole> roles,
                                                     std::string* error) {
  LinkCredentials credentials;
  credentials.own = ownPair(dir, roles, error);
  if (!credentials.own) return std::nullopt;
  const auto publics = filesEnding(dir, ".pub", error);
  if (!publics) return std::nullopt;
  std::vector<fs::path> robots;
  std::string robot_key;
  for (const auto& file : *publics) {
    std::string why;
    const auto key = readPublicKey(file, &why);
    if (!key) {
      *error = why;
      return std::nullopt;
    }
    if (key->role == LinkRole::kRobot) {
      robots.push_back(file);
      robot_key = key->public_z85;
    }
  }
  if (robots.empty()) {
    *error = dir.string() + ": no robot key here: copy the robot's .pub file (role robot) into this folder";
    return std::nullopt;
  }
  if (robots.size() > 1) {
    *error = dir.string() + ": more than one robot key (" + joined(robots) + "): keep the one of the robot to talk to";
    return std::nullopt;
  }
  credentials.robot_public_z85 = robot_key;
  return credentials;
}

}  // namespace telesphere::link::trust
