// SPDX-License-Identifier: MIT
/// @brief Chunk compression for MCAP: Zstandard (libzstd) and LZ4 frames (liblz4), the two the
///        specification names. Zstandard compresses JPEG-heavy chunks little and costs CPU; LZ4
///        is nearly free; none is the default for recordings of camera streams (measured in
///        `telesphere-bench record`).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot/record/mcap_format.h"

namespace telesphere::record {

/// Compresses `size` bytes into *out (replaced); kNone copies. Zstandard at `zstd_level`.
void compressChunk(McapCompression c, const std::uint8_t* data, std::size_t size, std::vector<std::uint8_t>* out,
                   int zstd_level = 1);

/// Decompresses into *out, which must come out exactly `uncompressed_size` bytes; false with
/// the reason for corrupt input or a size that does not match.
bool decompressChunk(McapCompression c, const std::uint8_t* data, std::size_t size, std::uint64_t uncompressed_size,
                     std::vector<std::uint8_t>* out, std::string* error);

}  // namespace telesphere::record
