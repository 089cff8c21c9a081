// SPDX-License-Identifier: MIT
/// @brief TELESPHERE_ROW_KERNEL: marks a per-row pixel loop to be built in two versions on x86-64,
///        picked once at start by the CPU (GCC's and Clang's function multi-versioning): AVX2's
///        32-byte vectors and 32-bit multiply where the CPU has them, SSE2 (every x86-64)
///        elsewhere. Other machines get their compiler's default vectors. Building with
///        -DTELESPHERE_ROW_KERNEL= keeps the default version alone (to test it on an AVX2 machine).
///        Kernels take their rows as __restrict parameters: GCC honours restrict there, not on
///        local pointers, and without it does not vectorise for the aliasing checks it would need.
#pragma once

#if !defined(TELESPHERE_ROW_KERNEL)
#if defined(__x86_64__) && defined(__ELF__)
#define TELESPHERE_ROW_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define TELESPHERE_ROW_KERNEL
#endif
#endif
