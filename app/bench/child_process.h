// SPDX-License-Identifier: MIT
/// @brief A program the benchmark starts beside itself (telesphere-robot, telesphere-xr), its
///        output in a log file; stopped with SIGINT and waited for. Killed if still running when
///        the object goes away.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::bench {

class ChildProcess {
 public:
  /// Starts argv[0] (a path) with stdout and stderr to `log_path`; running() false on failure.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool running() const { return pid_ > 0 && !status_; }
  /// Waits up to `timeout` for the exit; the exit code (128 + signal when killed), or nothing.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  /// SIGINT, then waits up to `timeout` (then SIGKILL); the exit code.
  int stop(std::chrono::milliseconds timeout = std::chrono::seconds(10));

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
};

}  // namespace telesphere::bench
