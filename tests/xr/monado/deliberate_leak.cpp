// SPDX-License-Identifier: MIT
/// @brief A leak of ours on purpose, for the proof that the Monado runs' leak check still fails on
///        our code (tests/xr/monado/openxr_monado_test.cpp, DeliberateLeakOfOursIsStillReported).
///        Preloaded into `telesphere-xr` by run_with_monado.sh --preload; its constructor, which the
///        side root's dynamic loader runs, allocates 4321 bytes and drops the only pointer.
#include <cstdlib>
#include <cstring>

extern "C" __attribute__((noinline, used)) void telesphere_test_deliberate_leak() {
  void* volatile block = std::malloc(4321);
  std::memset(block, 0x5a, 4321);
  block = nullptr;
}

__attribute__((constructor)) static void telesphere_test_deliberate_leak_at_load() { telesphere_test_deliberate_leak(); }
