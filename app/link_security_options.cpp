// SPDX-License-Identifier: MIT
/// @brief --keys / --insecure (see link_security_options.h).
#include "app/link_security_options.h"

#include <cstdio>

namespace telesphere::app {

void addLinkSecurityOptions(CLI::App& app, LinkSecurityOptions& options, const std::string& whose) {
  auto* keys = app.add_option("--keys", options.keys_dir,
                              "folder with " + whose + " (telesphere-keys generate; robot/link/README.md \"Keys\")");
  auto* insecure = app.add_flag("--insecure", options.insecure,
                                "no keys: plain TCP that anyone who reaches the ports may use to watch and move the "
                                "arm (warned every minute, shown red in the console and the headset)");
  keys->excludes(insecure);
}

std::optional<link::trust::LinkCredentials> linkCredentialsFrom(const LinkSecurityOptions& options,
                                                                std::initializer_list<link::trust::LinkRole> roles,
                                                                std::string* error) {
  if (options.insecure) return link::trust::LinkCredentials{};
  if (options.keys_dir.empty()) {
    *error = "the link needs keys: --keys DIR (make them with telesphere-keys generate), or --insecure to run "
             "without (anyone who reaches the ports could then watch and move the arm)";
    return std::nullopt;
  }
  if (!link::trust::curveAvailable()) {
    *error = "this libzmq has no CURVE (built without libsodium): keys cannot be used; install Debian's libzmq5";
    return std::nullopt;
  }
  const bool robot = roles.size() == 1 && *roles.begin() == link::trust::LinkRole::kRobot;
  return robot ? link::trust::loadRobotCredentials(options.keys_dir, error)
               : link::trust::loadClientCredentials(options.keys_dir, roles, error);
}

InsecureLinkWarning::InsecureLinkWarning(bool insecure, std::string program, std::chrono::seconds period) {
  if (!insecure) return;
  thread_ = std::thread([this, program = std::move(program), period] {
    std::unique_lock lock(mutex_);
    do {
      // On stderr: stdout may carry a program's output (`status --json`).
      std::fprintf(stderr,
                   "%s: WARNING: INSECURE LINK (--insecure): no keys; anyone who reaches the link's ports can watch "
                   "the cameras and move the arm. Use --keys DIR (telesphere-keys generate).\n",
                   program.c_str());
    } while (!stop_.wait_for(lock, period, [this] { return stopping_; }));
  });
}

InsecureLinkWarning::~InsecureLinkWarning() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace telesphere::app
