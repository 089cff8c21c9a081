// SPDX-License-Identifier: MIT
// @brief Sanitizer run-time defaults for every executable of a TELESPHERE_SANITIZE build (the tests,
//        the apps they start, the fuzz targets). The environment (ASAN_OPTIONS, LSAN_OPTIONS) still
//        overrides them.
//
// intercept_tls_get_addr=0: up to GCC 13 and LLVM 16 the runtime's __tls_get_addr interceptor takes a
// dynamic TLS block whose start lies 16 bytes past a page boundary for a pre-2.25 glibc header and reads
// the two words before it as a block's address and size. glibc 2.25+ has no such header, so when a
// block lands there by chance, LeakSanitizer's tracer follows garbage at exit and dies with "Tracer
// caught signal 11" after every test passed (seen once in CI in xr_operator_view_test, whose Mesa
// threads use dynamic TLS). Without the interceptor the tracer never reads those words.

extern "C" const char* __asan_default_options();  // NOLINT(bugprone-reserved-identifier)

extern "C" const char* __asan_default_options() {  // NOLINT(bugprone-reserved-identifier)
  return "intercept_tls_get_addr=0";
}

// Leaks that are not ours, in Debian's libraries: x265 3.5 keeps each encoder's frame-filter rows
// (FrameFilter::init, ~45 kB per encoder opened) past x265_encoder_close; H.264/HEVC tests open a
// few encoders (#34).
extern "C" const char* __lsan_default_suppressions();  // NOLINT(bugprone-reserved-identifier)

extern "C" const char* __lsan_default_suppressions() {  // NOLINT(bugprone-reserved-identifier)
  return "leak:libx265.so\n";
}
