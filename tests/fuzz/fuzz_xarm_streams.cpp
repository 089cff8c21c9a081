// SPDX-License-Identifier: MIT
/// @brief libFuzzer target: arbitrary bytes as the xArm controller's two streams (robot/arm/xarm/),
///        fed in chunks whose sizes the first byte sets, to the command-port frame reader and the
///        report-port report reader. They must never crash, read out of bounds or allocate beyond
///        a frame's limit, and a report they accept has finite joints and valid nibbles.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "robot/arm/xarm/xarm_protocol.h"
#include "robot/arm/xarm/xarm_report.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using namespace telesphere::xarm;
  const std::size_t chunk = 1 + data[0] % 97;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  FrameReader frames;
  ReportReader reports;
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    const auto piece = bytes.subspan(at, std::min(chunk, bytes.size() - at));
    frames.feed(piece);
    reports.feed(piece);
    while (auto f = frames.next())
      if (f->body.size() + 7 > kMaxFrameBytes) __builtin_trap();
    while (auto r = reports.next()) {
      if (r->state > 6 || r->mode > 11) __builtin_trap();
      for (double q : r->q)
        if (!std::isfinite(q)) __builtin_trap();
    }
  }
  return 0;
}
