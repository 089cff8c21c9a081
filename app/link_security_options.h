// SPDX-License-Identifier: MIT
/// @brief --keys DIR and --insecure, the same on every program (DESIGN.md §10). One of the two is
///        required: a program that would talk on an open link says so and exits, unless the user
///        chose --insecure, which then warns now and every minute while it runs.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <condition_variable>
#include <initializer_list>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "robot/link/trust/link_credentials.h"

namespace telesphere::app {

struct LinkSecurityOptions {
  std::string keys_dir;
  bool insecure = false;
};

/// Adds --keys and --insecure to `app` (they exclude each other). `whose` says in the help text
/// what the folder holds ("the robot's key pair and allowed/", "this program's key pair and the
/// robot's .pub").
void addLinkSecurityOptions(CLI::App& app, LinkSecurityOptions& options, const std::string& whose);

/// The credentials the options name: the robot's (`roles` = {robot}) or a client's. Nothing,
/// with a message for the user, when neither option was given or the folder is not usable; an
/// empty (insecure) LinkCredentials for --insecure.
std::optional<link::trust::LinkCredentials> linkCredentialsFrom(const LinkSecurityOptions& options,
                                                                std::initializer_list<link::trust::LinkRole> roles,
                                                                std::string* error);

/// While it lives on an insecure link: a warning at once and every `period` after, on stderr.
/// Nothing on a secure one.
class InsecureLinkWarning {
 public:
  InsecureLinkWarning(bool insecure, std::string program, std::chrono::seconds period = std::chrono::seconds(60));
  ~InsecureLinkWarning();
  InsecureLinkWarning(const InsecureLinkWarning&) = delete;
  InsecureLinkWarning& operator=(const InsecureLinkWarning&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable stop_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace telesphere::app
