// SPDX-License-Identifier: MIT
/// @brief Network namespaces: unshare, setns, loopback up, `ip`.
#include "app/bench/impairment/network_namespace.h"

#include <fcntl.h>
#include <net/if.h>
#include <sched.h>
#include <spawn.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

extern char** environ;

namespace telesphere::bench::impairment {
namespace {

std::string errnoText(const std::string& what) { return what + ": " + std::strerror(errno); }

bool loopbackUp(std::string* error) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    *error = errnoText("socket");
    return false;
  }
  ifreq request{};
  std::strncpy(request.ifr_name, "lo", IFNAMSIZ - 1);
  bool ok = ::ioctl(fd, SIOCGIFFLAGS, &request) == 0;
  if (ok) {
    request.ifr_flags = static_cast<short>(request.ifr_flags | IFF_UP);
    ok = ::ioctl(fd, SIOCSIFFLAGS, &request) == 0;
  }
  if (!ok) *error = errnoText("bringing loopback up");
  ::close(fd);
  return ok;
}

}  // namespace

bool enterPrivateNetworkNamespace(std::string* error) {
  if (::unshare(CLONE_NEWNET) != 0) {
    *error = errnoText("a network namespace of our own (needs CAP_NET_ADMIN: root, or `unshare -rn`)");
    return false;
  }
  return loopbackUp(error);
}

int makeNetworkNamespace(std::string* error) {
  int fd = -1;
  std::thread([&] {
    // A thread of its own: unshare moves only this thread, and the descriptor keeps the namespace.
    if (!enterPrivateNetworkNamespace(error)) return;
    fd = ::open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC);
    if (fd < 0) *error = errnoText("/proc/thread-self/ns/net");
  }).join();
  return fd;
}

bool runInNetworkNamespace(int ns_fd, const std::function<void()>& work, std::string* error) {
  bool entered = false;
  std::thread([&] {
    if (::setns(ns_fd, CLONE_NEWNET) != 0) {
      *error = errnoText("entering a network namespace");
      return;
    }
    entered = true;
    work();
  }).join();
  return entered;
}

bool runIp(const std::vector<std::string>& args, std::string* error) {
  std::vector<char*> argv{const_cast<char*>("ip")};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int spawned = posix_spawnp(&pid, "ip", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  std::string command = "ip";
  for (const std::string& a : args) command += " " + a;
  if (spawned != 0) {
    *error = command + ": cannot run ip (iproute2): " + std::strerror(spawned);
    return false;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return true;
  *error = command + ": exit " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status));
  return false;
}

}  // namespace telesphere::bench::impairment
