// SPDX-License-Identifier: MIT
/// @brief For the headless calibration tests: a `telesphere-robot --sim` child process on loopback
///        (its log in a file) and running a command with its stdout and stderr captured.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace telesphere::test {

struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr (the log)
};

/// Runs `command` through the shell; stderr goes through a file in `dir`.
inline CommandResult runCommand(const std::string& command, const std::string& dir) {
  CommandResult r;
  const std::string err_file = dir + "/stderr.txt";
  FILE* pipe = popen((command + " 2>" + err_file).c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_file);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  return r;
}

inline std::string fileText(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Starts `args` (args[0]: the binary) with stdout and stderr in `log`; after 2 s checks that it
/// still runs (a robot that exits at once, e.g. its port taken by a stale one, must not leave
/// the tests talking to somebody else's robot). -1 with *error set otherwise.
inline pid_t spawnRobot(std::vector<std::string> args, const std::string& log, std::string* error) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0].c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    *error = "cannot start " + args[0];
    return -1;
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));
  int status = 0;
  if (waitpid(pid, &status, WNOHANG) == pid) {
    *error = "telesphere-robot exited at start:\n" + fileText(log);
    return -1;
  }
  return pid;
}

inline void stopRobot(pid_t pid) {
  if (pid <= 0) return;
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
}

}  // namespace telesphere::test
