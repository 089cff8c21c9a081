// SPDX-License-Identifier: MIT
/// @brief Repair requests: writing and checked parsing.
#include "robot/link/media/repair_request.h"

#include <algorithm>

#include "robot/link/media/big_endian.h"

namespace telesphere::link::media {
using big_endian::get16;
using big_endian::get32;
using big_endian::put16;
using big_endian::put32;

void writeRepairRequest(const RepairRequest& r, std::vector<std::uint8_t>& out) {
  const std::size_t n = std::min(r.chunks.size(), kMaxRepairChunks);
  put16(out, kMediaMagic);
  out.push_back(kMediaVersion);
  out.push_back(kRepairRequestKind);
  put16(out, 0);
  put32(out, r.stream);
  put32(out, r.receiver);
  put32(out, r.frame);
  put16(out, static_cast<std::uint16_t>(n));
  put16(out, 0);
  for (std::size_t i = 0; i < n; ++i) put16(out, r.chunks[i]);
}

std::optional<RepairRequest> parseRepairRequest(std::span<const std::uint8_t> b, MediaDropReason* why) {
  const auto refuse = [&](MediaDropReason reason) -> std::optional<RepairRequest> {
    *why = reason;
    return std::nullopt;
  };
  if (b.size() < kRepairRequestHeaderBytes || get16(b.data()) != kMediaMagic) return refuse(MediaDropReason::kMalformed);
  if (b[2] != kMediaVersion) return refuse(MediaDropReason::kWrongVersion);
  if (b[3] != kRepairRequestKind || get16(&b[4]) != 0 || get16(&b[20]) != 0) return refuse(MediaDropReason::kMalformed);
  RepairRequest r;
  r.stream = get32(&b[6]);
  r.receiver = get32(&b[10]);
  r.frame = get32(&b[14]);
  const std::size_t n = get16(&b[18]);
  if (n == 0 || n > kMaxRepairChunks || b.size() != kRepairRequestHeaderBytes + 2 * n || r.receiver == 0)
    return refuse(MediaDropReason::kMalformed);
  r.chunks.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t chunk = get16(&b[kRepairRequestHeaderBytes + 2 * i]);
    if (!r.chunks.empty() && chunk <= r.chunks.back()) return refuse(MediaDropReason::kMalformed);
    r.chunks.push_back(chunk);
  }
  return r;
}

}  // namespace telesphere::link::media
