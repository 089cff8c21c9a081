// SPDX-License-Identifier: MIT
/// @brief Key files (see link_key_files.h).
#include "robot/link/trust/link_key_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace telesphere::link::trust {
namespace {

namespace fs = std::filesystem;

std::string yamlOf(const LinkKeyPair& pair, bool with_secret) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << pair.key.name;
  out << YAML::Key << "role" << YAML::Value << std::string(linkRoleName(pair.key.role));
  out << YAML::Key << "public_key" << YAML::Value << YAML::DoubleQuoted << pair.key.public_z85;
  if (with_secret) out << YAML::Key << "secret_key" << YAML::Value << YAML::DoubleQuoted << pair.secret_z85;
  out << YAML::EndMap;
  const std::string header = with_secret
                                 ? "# telesphere link key: SECRET. Keep it on this machine, mode 0600; never copy it.\n"
                                 : "# telesphere link key (public): give it to the peers that should trust " +
                                       pair.key.name + " as " + std::string(linkRoleName(pair.key.role)) + ".\n";
  return header + out.c_str() + "\n";
}

/// Writes `text` to `file` with `mode` through a temporary file renamed into place.
bool writeFile(const fs::path& file, const std::string& text, mode_t mode, std::string* error) {
  std::string temporary_name = file.filename().string();
  temporary_name.insert(0, 1, '.');
  temporary_name += ".tmp";
  const fs::path temporary = file.parent_path() / temporary_name;
  ::unlink(temporary.c_str());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  if (fd < 0) {
    *error = temporary.string() + ": " + std::strerror(errno);
    return false;
  }
  // The umask may have taken bits away, never added any; a public key is meant to be read.
  bool ok = ::fchmod(fd, mode) == 0;
  std::size_t done = 0;
  while (ok && done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) ok = false;
    else done += std::size_t(n);
  }
  ok = ok && ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  if (!ok || std::rename(temporary.c_str(), file.c_str()) != 0) {
    *error = file.string() + ": " + std::strerror(ok ? errno : saved);
    ::unlink(temporary.c_str());
    return false;
  }
  return true;
}

std::optional<LinkKeyPair> parse(const fs::path& file, bool want_secret, std::string* error) {
  const auto fail = [&](const std::string& why) -> std::optional<LinkKeyPair> {
    *error = file.string() + ": " + why;
    return std::nullopt;
  };
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    return fail(std::string("cannot read it (") + std::strerror(errno) + ")");
  } catch (const YAML::Exception& e) {
    return fail(std::string("not a key file: ") + e.what());
  }
  if (!root.IsMap()) return fail("not a key file (no name, role, public_key)");
  LinkKeyPair pair;
  try {
    for (const char* field : {"name", "role", "public_key"})
      if (!root[field] || !root[field].IsScalar()) return fail(std::string("no ") + field);
    pair.key.name = root["name"].as<std::string>();
    if (const std::string why = checkKeyName(pair.key.name); !why.empty()) return fail(why);
    const auto role = parseLinkRole(root["role"].as<std::string>());
    if (!role) return fail("role \"" + root["role"].as<std::string>() + "\" is not one of " + linkRoleChoices());
    pair.key.role = *role;
    pair.key.public_z85 = root["public_key"].as<std::string>();
    if (want_secret) {
      if (!root["secret_key"] || !root["secret_key"].IsScalar()) return fail("no secret_key (is it the .pub file?)");
      pair.secret_z85 = root["secret_key"].as<std::string>();
    }
  } catch (const YAML::Exception& e) {
    return fail(e.what());
  }
  if (pair.key.public_z85.size() != 40) return fail("public_key is not a 40-character Z85 key");
  return pair;
}

}  // namespace

std::optional<KeyPairPaths> writeKeyPair(const LinkKeyPair& pair, const fs::path& dir, bool replace, std::string* error) {
  if (const std::string why = checkKeyName(pair.key.name); !why.empty()) {
    *error = why;
    return std::nullopt;
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    *error = dir.string() + ": cannot create the folder: " + ec.message();
    return std::nullopt;
  }
  const KeyPairPaths paths{dir / (pair.key.name + ".pub"), dir / (pair.key.name + ".secret")};
  if (!replace) {
    for (const fs::path& p : {paths.public_file, paths.secret_file})
      if (fs::exists(p, ec)) {
        *error = p.string() + " exists: a key of that name is there already (--force replaces it, and every peer "
                              "that trusted it must be given the new .pub)";
        return std::nullopt;
      }
  }
  if (!writeFile(paths.secret_file, yamlOf(pair, true), 0600, error)) return std::nullopt;
  if (!writeFile(paths.public_file, yamlOf(pair, false), 0644, error)) return std::nullopt;
  return paths;
}

std::optional<LinkKey> readPublicKey(const fs::path& file, std::string* error) {
  auto pair = parse(file, false, error);
  if (!pair) return std::nullopt;
  return pair->key;
}

std::optional<LinkKeyPair> readKeyPair(const fs::path& secret_file, std::string* error) {
  struct stat st {};
  if (::stat(secret_file.c_str(), &st) != 0) {
    *error = secret_file.string() + ": " + std::strerror(errno);
    return std::nullopt;
  }
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", unsigned(st.st_mode & 07777));
    *error = secret_file.string() + ": the secret key may be read by " + ((st.st_mode & 007) ? "anyone" : "its group") +
             " (mode " + mode + "): chmod 600 " + secret_file.string();
    return std::nullopt;
  }
  auto pair = parse(secret_file, true, error);
  if (!pair) return std::nullopt;
  const auto public_z85 = publicKeyOf(pair->secret_z85);
  if (!public_z85) {
    *error = secret_file.string() + ": secret_key is not a 40-character Z85 CURVE key";
    return std::nullopt;
  }
  if (*public_z85 != pair->key.public_z85) {
    *error = secret_file.string() + ": public_key is not the one its secret_key makes (the file was edited or mixed up)";
    return std::nullopt;
  }
  return pair;
}

}  // namespace telesphere::link::trust
