// SPDX-License-Identifier: MIT
/// @brief Retransmission on the media path (DESIGN.md §9), operator → robot: the chunks of a
///        frame the receiver misses and its parity cannot rebuild. The sender sends them again
///        only while that frame is still the newest it has begun sending: a frame a newer one
///        superseded is never repaired.
///        Layout, big-endian: magic u16, version u8, kind u8 (6), reserved u16, stream u32,
///        receiver u32, frame u32, count u16, reserved u16, then count × chunk index u16.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "robot/link/media/media_packet.h"

namespace telesphere::link::media {

inline constexpr std::uint8_t kRepairRequestKind = 6;
inline constexpr std::size_t kRepairRequestHeaderBytes = 22;
inline constexpr std::size_t kMaxRepairChunks = (kMaxMediaDatagramBytes - kRepairRequestHeaderBytes) / 2;

struct RepairRequest {
  std::uint32_t stream = 0;    ///< the sender's stream
  std::uint32_t receiver = 0;  ///< as in the receiver's reports
  std::uint32_t frame = 0;
  std::vector<std::uint16_t> chunks;  ///< ascending
};

/// Appends one datagram; chunks beyond kMaxRepairChunks are not written.
void writeRepairRequest(const RepairRequest& request, std::vector<std::uint8_t>& out);
/// A repair request, or nothing (kMalformed, kWrongVersion) for anything else: no chunks, chunks
/// not ascending, a count that disagrees with the size, receiver 0.
std::optional<RepairRequest> parseRepairRequest(std::span<const std::uint8_t> bytes, MediaDropReason* why);

}  // namespace telesphere::link::media
