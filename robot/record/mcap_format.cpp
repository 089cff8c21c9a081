// SPDX-License-Identifier: MIT
/// @brief Compression names and the CRC (see mcap_format.h).
#include "robot/record/mcap_format.h"

#include <zlib.h>

#include <limits>

namespace telesphere::record {

std::string_view compressionName(McapCompression c) {
  switch (c) {
    case McapCompression::kNone: return "";
    case McapCompression::kZstd: return "zstd";
    case McapCompression::kLz4: return "lz4";
  }
  return "";
}

std::optional<McapCompression> parseCompression(std::string_view name) {
  if (name.empty() || name == "none") return McapCompression::kNone;
  if (name == "zstd") return McapCompression::kZstd;
  if (name == "lz4") return McapCompression::kLz4;
  return std::nullopt;
}

std::uint32_t mcapCrc32(const void* data, std::size_t size, std::uint32_t crc) {
  const auto* p = static_cast<const Bytef*>(data);
  uLong c = crc;
  while (size > 0) {  // zlib takes uInt lengths
    const auto n = static_cast<uInt>(std::min<std::size_t>(size, std::numeric_limits<uInt>::max()));
    c = crc32(c, p, n);
    p += n;
    size -= n;
  }
  return static_cast<std::uint32_t>(c);
}

}  // namespace telesphere::record
