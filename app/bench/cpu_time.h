// SPDX-License-Identifier: MIT
/// @brief Clocks for the benchmark topics that measure what a stage costs a core: this thread's
///        CPU time (what one core does when the machine is shared), the process's, the wall clock,
///        and the rate of repeated calls by each.
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <ctime>

namespace telesphere::bench {

inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

inline double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

inline double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Frames per second of `reps` calls of f on this thread: by wall time and by this thread's CPU
/// time.
struct Rate {
  double fps_wall = 0, fps_cpu = 0, ms_per_frame_cpu = 0;
};

template <typename F>
Rate measureRate(int reps, F f) {
  f();  // warm-up: buffers sized, caches primed
  const double w0 = wallSeconds(), c0 = threadCpuSeconds();
  for (int i = 0; i < reps; ++i) f();
  const double wall = wallSeconds() - w0, cpu = threadCpuSeconds() - c0;
  return {reps / wall, reps / cpu, 1e3 * cpu / reps};
}

}  // namespace telesphere::bench
