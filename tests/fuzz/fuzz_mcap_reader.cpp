// SPDX-License-Identifier: MIT
/// @brief libFuzzer target: arbitrary bytes as an MCAP file (robot/record/mcap_reader). The
///        summary (from the summary section and by scanning) and every message, in both the strict
///        and the stop-at-damage read, must never crash, read out of bounds or allocate beyond a
///        chunk's 4 GiB limit; every message handed out lies inside the file or its chunk.
#include <cstddef>
#include <cstdint>
#include <string>

#include "robot/record/mcap_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace telesphere::record;
  std::string error;
  const auto reader = McapReader::fromBytes(data, size, &error);
  if (!reader) return 0;
  McapSummary summary;
  (void)reader->summary(&summary, &error);
  (void)reader->summary(&summary, &error, true);
  std::uint64_t sum = 0;
  for (const bool stop_at_damage : {false, true}) {
    McapDamage damage;
    (void)reader->forEachMessage(
        [&](const McapMessageView& m) {
          if (m.size > 0) sum += m.data[0] + m.data[m.size - 1];  // ASan checks both ends
          return true;
        },
        &error, stop_at_damage, &damage);
  }
  return sum == 0x7fffffff ? 1 : 0;
}
