// SPDX-License-Identifier: MIT
/// @brief telesphere-keys: key pairs for the link's programs (DESIGN.md §10).
///          generate --role R --name N --out DIR [--force]   DIR/N.pub and DIR/N.secret (0600)
///          show FILE...                                      name, role and public key; a secret
///                                                            file is checked (mode, pair)
///        Exit codes: 0 ok, 1 bad arguments or files, 2 this libzmq has no CURVE.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "robot/link/trust/link_key_files.h"
#include "robot/link/trust/link_key_pair.h"

namespace {

namespace trust = telesphere::link::trust;

int generate(const std::string& role_name, const std::string& name, const std::string& out, bool replace) {
  const auto role = trust::parseLinkRole(role_name);
  if (!role) {
    std::cerr << "telesphere-keys: --role must be one of " << trust::linkRoleChoices() << ", got \"" << role_name << "\"\n";
    return 1;
  }
  if (!trust::curveAvailable()) {
    std::cerr << "telesphere-keys: this libzmq has no CURVE (built without libsodium): no keys can be made or used\n";
    return 2;
  }
  std::string error;
  const auto pair = trust::generateKeyPair(name, *role, &error);
  if (!pair) {
    std::cerr << "telesphere-keys: " << error << '\n';
    return 1;
  }
  const auto paths = trust::writeKeyPair(*pair, out, replace, &error);
  if (!paths) {
    std::cerr << "telesphere-keys: " << error << '\n';
    return 1;
  }
  std::printf("%s (%s): public key %s\n  %s  give it to the peers that should trust %s\n  %s  keep it here (mode 0600)\n",
              name.c_str(), role_name.c_str(), pair->key.public_z85.c_str(), paths->public_file.c_str(), name.c_str(),
              paths->secret_file.c_str());
  return 0;
}

int show(const std::vector<std::string>& files) {
  int code = 0;
  for (const std::string& file : files) {
    std::string error;
    const bool secret = file.size() > 7 && file.compare(file.size() - 7, 7, ".secret") == 0;
    std::optional<trust::LinkKey> key;
    if (secret) {
      if (const auto pair = trust::readKeyPair(file, &error)) key = pair->key;
    } else {
      key = trust::readPublicKey(file, &error);
    }
    if (!key) {
      std::cerr << "telesphere-keys: " << error << '\n';
      code = 1;
      continue;
    }
    std::printf("%s: %s (%s), public key %s%s\n", file.c_str(), key->name.c_str(),
                std::string(trust::linkRoleName(key->role)).c_str(), key->public_z85.c_str(),
                secret ? "; secret key readable by its owner only, and the pair matches" : "");
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"telesphere-keys: key pairs for the link's programs, each with its role (DESIGN.md §10)"};
  app.require_subcommand(1);
  std::string role, name, out;
  bool replace = false;
  std::vector<std::string> files;
  auto* g = app.add_subcommand("generate", "a new key pair: DIR/NAME.pub (for the peers) and DIR/NAME.secret (0600)");
  g->add_option("--role", role, trust::linkRoleChoices())->required();
  g->add_option("--name", name, "who holds it (A–Z a–z 0–9 . _ -), as the supervisor will read it")->required();
  g->add_option("--out", out, "the folder to write into (made if missing)")->required();
  g->add_flag("--force", replace, "replace a key of that name (every peer that trusted it needs the new .pub)");
  auto* s = app.add_subcommand("show", "name, role and public key of key files; a .secret file is checked too");
  s->add_option("files", files, "NAME.pub or NAME.secret files")->required();
  CLI11_PARSE(app, argc, argv);
  if (g->parsed()) return generate(role, name, out, replace);
  return show(files);
}
