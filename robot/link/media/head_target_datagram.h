// SPDX-License-Identifier: MIT
/// @brief Head targets on the media path (DESIGN.md §9), operator → robot: every datagram carries
///        the last few targets (newest last), so a lost datagram costs nothing as long as one of
///        the next few arrives, and nothing waits behind a loss as on TCP. The robot keeps the
///        newest by t_ns per sender instance (LinkServer::offerHeadTarget), whichever path it came by.
///        Layout, big-endian: magic u16, version u8, kind u8 (5), reserved u16, count u8,
///        reserved u8, then count × (bytes u16, a HeadTarget protobuf).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "robot/link/media/media_packet.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link::media {

inline constexpr std::uint8_t kHeadTargetsKind = 5;
inline constexpr std::size_t kHeadTargetsHeaderBytes = 8;
/// Targets repeated per datagram: at 90 Hz, three cover 33 ms of lost datagrams.
inline constexpr std::size_t kHeadTargetsRepeated = 3;

/// Appends one datagram with `targets` (at most 8; each at most 400 bytes serialised, a HeadTarget
/// is about 100).
void writeHeadTargets(std::span<const proto::HeadTarget> targets, std::vector<std::uint8_t>& out);
/// The targets of a head-target datagram, oldest first; nothing (kMalformed, kWrongVersion) for
/// anything else or a target that does not parse.
std::optional<std::vector<proto::HeadTarget>> parseHeadTargets(std::span<const std::uint8_t> bytes, MediaDropReason* why);

}  // namespace telesphere::link::media
