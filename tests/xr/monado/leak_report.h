// SPDX-License-Identifier: MIT
/// @brief What the sanitizers printed in a process that ran against a foreign runtime (Monado and
///        Mesa from a Debian trixie side root): each LeakSanitizer block sorted into ours or foreign
///        by its *allocating frame* (the first frame outside the sanitizer runtime), every other
///        sanitizer report kept as a failure.
///
/// Why not a suppression file: LeakSanitizer suppresses a leak when *any* frame of its stack
/// matches, and in a process started through the side root's dynamic loader every stack of ours
/// ends in that root (`__libc_start_call_main`, `start_thread`, `_dl_init`). Suppressing by the
/// root's location would hide our own leaks; suppressing by one library's name breaks at the next
/// Mesa update. The allocating frame is the narrowest fact that says whose allocation it was.
///
/// Limit: an allocation made inside the root's libc or libstdc++ on behalf of our code (an
/// unclosed `fopen`) counts as foreign here; the same code runs under bookworm's libc in every
/// other test, where it is caught.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace telesphere::test {

/// One "Direct/Indirect leak of N byte(s) in M object(s) allocated from:" block.
struct LeakBlock {
  bool direct = true;
  long long bytes = 0;
  long long objects = 0;
  std::vector<std::string> frames;  ///< "#k 0x… in f (module+0x…)" lines, trimmed
  /// Index into `frames` of the first frame outside the sanitizer runtime; frames.size() if none.
  std::size_t allocating_frame = 0;
  std::string text;  ///< the block as printed

  /// The allocating frame's text, or "" when every frame is the sanitizer's own.
  std::string allocatingFrame() const;
  /// The file name of the allocating frame's module or source ("libgallium-25.0.7.so"), or "?".
  std::string allocatingModule() const;
};

struct SanitizerFindings {
  std::vector<LeakBlock> ours;     ///< allocated in our code (or nowhere identifiable): failures
  std::vector<LeakBlock> foreign;  ///< allocated in a library of a foreign root: reported, not failed
  /// Sanitizer reports that are not leak blocks (heap-buffer-overflow, "runtime error:", a crashed
  /// leak tracer): each its first line. Always failures.
  std::vector<std::string> other_reports;

  long long foreignBytes() const;
  /// "3 foreign leak blocks (2352 bytes) allocated in libgallium-25.0.7.so ×2, ld-linux-x86-64.so.2 ×1".
  std::string foreignSummary() const;
  /// Every block of ours and every other report, as printed (for a failure message).
  std::string oursText() const;
};

/// True when `frame` (a stack-frame line) lies in the sanitizer runtime itself (the interceptor or
/// operator new that every allocation passes through).
bool isSanitizerRuntimeFrame(const std::string& frame);

/// Sorts the sanitizer output in `output` (stdout and stderr of a process, other lines mixed in).
/// A leak block is foreign when its allocating frame names a path under one of `foreign_roots`
/// (absolute folders; a trailing '/' is optional). Output without sanitizer reports gives empty
/// findings.
SanitizerFindings classifySanitizerOutput(const std::string& output, const std::vector<std::string>& foreign_roots);

}  // namespace telesphere::test
