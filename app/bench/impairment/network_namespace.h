// SPDX-License-Identifier: MIT
/// @brief Network namespaces for measurements on IP packets (DESIGN.md §9): a private namespace
///        for the calling thread (only loopback, up), a new one kept open by a descriptor, and
///        work — a thread, a process, an `ip` command — run inside one. Needs CAP_NET_ADMIN (root
///        here; `unshare -rn` gives it without root). Nothing here touches the machine's own
///        network: what is made in a namespace goes away with its last user.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace telesphere::bench::impairment {

/// Moves the calling thread into a new network namespace with loopback up; threads and processes
/// it starts afterwards are in it too. False with the reason in *error.
bool enterPrivateNetworkNamespace(std::string* error);

/// A new network namespace with loopback up, held open by the returned descriptor (close it to
/// let the namespace go once nothing runs in it); −1 with the reason in *error.
int makeNetworkNamespace(std::string* error);

/// Runs `work` on a thread that has entered the namespace `ns_fd`, and waits for it. False with
/// the reason in *error when the thread could not enter it (then `work` did not run).
bool runInNetworkNamespace(int ns_fd, const std::function<void()>& work, std::string* error);

/// Runs `ip ARGS…` (iproute2) in the calling thread's namespace and waits; false with its exit
/// status in *error.
bool runIp(const std::vector<std::string>& args, std::string* error);

}  // namespace telesphere::bench::impairment
