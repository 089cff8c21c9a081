// SPDX-License-Identifier: MIT
/// @brief The Monado runs' leak classification on reports as GCC 12's LeakSanitizer prints them:
///        a block is foreign only when its allocating frame lies in the side root, so a leak of
///        ours whose deeper frames pass through the root's loader or libc still fails.
#include <gtest/gtest.h>

#include "tests/xr/monado/leak_report.h"

namespace telesphere::test {
namespace {

const std::string kRoot = "/var/cache/telesphere/monado-trixie";

// The report of issue #29 (a fresh root's Mesa), the loader's dlopen leak, and a leak of ours
// allocated in a constructor that the root's loader ran: its third frame lies in the root.
const std::string kReport = R"(frames: submitted 12, waited 12
run_with_monado: stopping the service

=================================================================
==4242==ERROR: LeakSanitizer: detected memory leaks

Direct leak of 2352 byte(s) in 49 object(s) allocated from:
    #0 0x7f3c1b6b89cf in __interceptor_malloc ../../../../src/libsanitizer/asan/asan_malloc_linux.cpp:69
    #1 0x7f3c0e573b01  (/var/cache/telesphere/monado-trixie/usr/lib/x86_64-linux-gnu/libgallium-25.0.7-2+deb13u1.so+0x573b01)

Direct leak of 4321 byte(s) in 1 object(s) allocated from:
    #0 0x7f3c1b6b89cf in __interceptor_malloc ../../../../src/libsanitizer/asan/asan_malloc_linux.cpp:69
    #1 0x7f3c1b2a1139 in telesphere_test_deliberate_leak /work/main/tests/xr/monado/deliberate_leak.cpp:20
    #2 0x7f3c1b8d247d in call_init (/var/cache/telesphere/monado-trixie/lib64/ld-linux-x86-64.so.2+0x647d)

Indirect leak of 64 byte(s) in 2 object(s) allocated from:
    #0 0x7f3c1b6ba1b7 in operator new(unsigned long) ../../../../src/libsanitizer/asan/asan_new_delete.cpp:99
    #1 0x55d1c0a12345 in telesphere::xr::OpenXrSession::create() /work/main/xr/openxr/openxr_session.cpp:120
    #2 0x7f3c1a029d8f in __libc_start_call_main (/var/cache/telesphere/monado-trixie/lib/x86_64-linux-gnu/libc.so.6+0x29d8f)

Direct leak of 80 byte(s) in 4 object(s) allocated from:
    #0 0x7f3c1b6b89cf in calloc (/lib/x86_64-linux-gnu/libasan.so.8+0xbd9cf)
    #1 0x7f3c1b8c1a2e  (/var/cache/telesphere/monado-trixie/lib64/ld-linux-x86-64.so.2+0x1a2e)

SUMMARY: AddressSanitizer: 6817 byte(s) leaked in 56 allocation(s).
)";

TEST(LeakReport, SortsBlocksByTheirAllocatingFrame) {
  const SanitizerFindings f = classifySanitizerOutput(kReport, {kRoot});
  ASSERT_EQ(f.foreign.size(), 2u);
  ASSERT_EQ(f.ours.size(), 2u);
  EXPECT_TRUE(f.other_reports.empty()) << f.oursText();

  EXPECT_EQ(f.foreign[0].bytes, 2352);
  EXPECT_EQ(f.foreign[0].objects, 49);
  EXPECT_EQ(f.foreign[0].allocatingModule(), "libgallium-25.0.7-2+deb13u1.so");
  EXPECT_EQ(f.foreign[1].allocatingModule(), "ld-linux-x86-64.so.2");
  EXPECT_EQ(f.foreignBytes(), 2352 + 80);
  EXPECT_EQ(f.foreignSummary(),
            "2 foreign leak blocks (2432 bytes) allocated in ld-linux-x86-64.so.2 ×1, "
            "libgallium-25.0.7-2+deb13u1.so ×1");

  // Ours although the root's loader and libc are on their stacks.
  EXPECT_TRUE(f.ours[0].direct);
  EXPECT_EQ(f.ours[0].bytes, 4321);
  EXPECT_EQ(f.ours[0].allocating_frame, 1u);
  EXPECT_NE(f.ours[0].allocatingFrame().find("telesphere_test_deliberate_leak"), std::string::npos);
  EXPECT_EQ(f.ours[0].allocatingModule(), "deliberate_leak.cpp");
  EXPECT_FALSE(f.ours[1].direct);
  EXPECT_NE(f.ours[1].allocatingFrame().find("OpenXrSession::create"), std::string::npos);
  EXPECT_NE(f.oursText().find("Direct leak of 4321 byte(s)"), std::string::npos);
}

TEST(LeakReport, ASuppressionByTheRootsLocationWouldHideOurLeaks) {
  // What LeakSanitizer's `leak:<root>` would do (any frame matches): the classification above
  // must not collapse to it.
  const SanitizerFindings f = classifySanitizerOutput(kReport, {kRoot});
  for (const LeakBlock& ours : f.ours) {
    bool any_frame_in_root = false;
    for (const std::string& frame : ours.frames) any_frame_in_root = any_frame_in_root || frame.find(kRoot) != std::string::npos;
    EXPECT_TRUE(any_frame_in_root) << ours.text;
  }
}

TEST(LeakReport, RootsMatchAsFoldersWithOrWithoutATrailingSlash) {
  EXPECT_EQ(classifySanitizerOutput(kReport, {kRoot + "/"}).foreign.size(), 2u);
  // A sibling folder whose name starts like the root is not the root.
  EXPECT_EQ(classifySanitizerOutput(kReport, {"/var/cache/telesphere/monado"}).foreign.size(), 0u);
  // No roots: everything is ours.
  EXPECT_EQ(classifySanitizerOutput(kReport, {}).ours.size(), 4u);
}

TEST(LeakReport, EveryOtherSanitizerReportIsKept) {
  const std::string text = R"(starting
==77==ERROR: AddressSanitizer: heap-buffer-overflow on address 0x602000000011
xr/render/foo.cpp:12:5: runtime error: signed integer overflow
Tracer caught signal 11: addr=0x0 pc=0x7f sp=0x7f
==77==LeakSanitizer has encountered a fatal error.
AddressSanitizer:DEADLYSIGNAL
done
)";
  const SanitizerFindings f = classifySanitizerOutput(text, {kRoot});
  EXPECT_EQ(f.other_reports.size(), 5u) << f.oursText();
  EXPECT_TRUE(f.ours.empty());
  EXPECT_TRUE(f.foreign.empty());
}

TEST(LeakReport, CleanOutputHasNoFindings) {
  const SanitizerFindings f = classifySanitizerOutput("focused: yes\nsubmitted 12\n", {kRoot});
  EXPECT_TRUE(f.ours.empty());
  EXPECT_TRUE(f.foreign.empty());
  EXPECT_TRUE(f.other_reports.empty());
  EXPECT_EQ(f.foreignSummary(), "0 foreign leak blocks (0 bytes)");
}

TEST(LeakReport, ABlockOfOnlyRuntimeFramesIsOurs) {
  const std::string text =
      "Direct leak of 8 byte(s) in 1 object(s) allocated from:\n"
      "    #0 0x7f in __interceptor_malloc ../../../../src/libsanitizer/asan/asan_malloc_linux.cpp:69\n";
  const SanitizerFindings f = classifySanitizerOutput(text, {kRoot});
  ASSERT_EQ(f.ours.size(), 1u);
  EXPECT_EQ(f.ours[0].allocatingFrame(), "");
  EXPECT_EQ(f.ours[0].allocatingModule(), "?");
}

}  // namespace
}  // namespace telesphere::test
