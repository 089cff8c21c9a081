// SPDX-License-Identifier: MIT
/// @brief Finishes an MCAP file that was cut off (the recording process killed, the disk full):
///        every message of the intact part — up to the first incomplete or corrupt record — is
///        written to a new, complete file with its schemas and channels, summary and footer.
#pragma once

#include <cstdint>
#include <string>

#include "robot/record/mcap_writer.h"

namespace telesphere::record {

struct McapRecoverReport {
  std::uint64_t messages = 0;         ///< kept
  std::uint64_t intact_bytes = 0;     ///< of the damaged file, read up to here
  std::uint64_t file_bytes = 0;       ///< the damaged file's size
  std::string damage;                 ///< what ended the intact part (empty: the file was whole)
};

/// Reads `in` up to its first damage and writes what it holds to `out` (compression from
/// `options`). False with the reason when `in` is not MCAP or `out` cannot be written.
bool recoverMcap(const std::string& in, const std::string& out, const McapWriterOptions& options,
                 McapRecoverReport* report, std::string* error);

}  // namespace telesphere::record
