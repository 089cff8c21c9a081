// SPDX-License-Identifier: MIT
/// @brief Programmer-error checks (STYLE.md §10, §13): in debug builds a failed precondition prints
///        the expression, file:line and the offending values, then aborts. Compiled out in NDEBUG.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace telesphere::detail {

template <typename... Values>
[[noreturn]] void assertFailed(const char* expression, const char* file, int line,
                               const Values&... values) {
  std::ostringstream os;
  ((os << ' ' << values), ...);
  std::fprintf(stderr, "%s:%d: assertion failed: %s;%s\n", file, line, expression,
               os.str().c_str());
  std::abort();
}

}  // namespace telesphere::detail

/// TS_ASSERT(condition, values...): values are streamed into the message when the condition fails.
#ifdef NDEBUG
#define TS_ASSERT(condition, ...) static_cast<void>(0)
#else
#define TS_ASSERT(condition, ...)                                                       \
  ((condition) ? static_cast<void>(0)                                                  \
               : ::telesphere::detail::assertFailed(#condition, __FILE__,             \
                                                    __LINE__ __VA_OPT__(, ) __VA_ARGS__))
#endif
