// SPDX-License-Identifier: MIT
/// @brief The link's schema rules beyond the .proto: the version we speak, limits that keep a bad
///        or hostile message from allocating absurd memory, and parsing that turns any byte string
///        into either a valid Envelope or a counted DropReason (never a crash).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link {

/// Bumped on any incompatible change of telesphere_link.proto (2: the mode became an enum;
/// telemetry, health, preview and the console's controls were added).
inline constexpr std::uint32_t kSchemaVersion = 2;
/// Largest image side we accept (8K); a 100000×100000 claim is dropped before anything allocates.
inline constexpr std::uint32_t kMaxImageSide = 8192;
/// Largest JPEG part we accept (a 8K×8K 4:4:4 JPEG at quality 100 stays below this).
inline constexpr std::size_t kMaxJpegBytes = std::size_t{256} << 20;
/// Largest envelope (the protobuf part of any message).
inline constexpr std::size_t kMaxEnvelopeBytes = std::size_t{1} << 20;
/// Largest control reply the client accepts: a calibration still carries both images at full
/// resolution in grey (up to two kMaxImageSide² images) besides the usual reply.
inline constexpr std::size_t kMaxControlReplyBytes =
    2 * std::size_t{kMaxImageSide} * std::size_t{kMaxImageSide} + kMaxEnvelopeBytes;

/// Why a message was dropped; counted per reason (LinkStats) and logged.
enum class DropReason : int {
  kGarbage,              ///< not a protobuf Envelope, or one without a body
  kWrongSchemaVersion,   ///< another schema version
  kUnexpectedBody,       ///< a valid message on a channel that does not carry it
  kBadPartCount,         ///< a stereo frame without exactly two image parts (or parts elsewhere)
  kBadImageSize,         ///< zero or beyond kMaxImageSide, or a part size that disagrees
  kOversized,            ///< an envelope or JPEG part beyond its limit
  kSuperseded,           ///< a newer frame arrived before this one was taken (latest wins), or
                         ///< a head target older than one its sender already sent
  kCorruptJpeg,          ///< the JPEG did not decode (operator side)
  kRefused,              ///< the sender's key may not send it (DESIGN.md §10; counted as a refusal too)
  kCount
};

std::string_view dropReasonName(DropReason reason);

/// A random non-zero id for one process's link endpoint (server instance, head-target sender).
std::uint64_t newLinkInstanceId();

/// Parses bytes into an Envelope of our schema version with a body; otherwise nothing and *why.
/// For kWrongSchemaVersion, *peer_version (when given) is the version the sender spoke.
/// Envelopes beyond max_bytes are kOversized.
std::optional<proto::Envelope> parseEnvelope(const void* data, std::size_t size, DropReason* why,
                                             std::uint32_t* peer_version = nullptr,
                                             std::size_t max_bytes = kMaxEnvelopeBytes);

/// Both images of `frame` are JPEGs (MJPEG: each stands alone), not H.264/HEVC access units.
inline bool carriesJpegs(const proto::StereoFrame& frame) {
  return frame.left().codec() == proto::VIDEO_CODEC_MJPEG && frame.right().codec() == proto::VIDEO_CODEC_MJPEG;
}

/// Checks a stereo frame's description against the sizes of its two image parts.
std::optional<DropReason> checkStereoFrame(const proto::StereoFrame& frame, std::size_t left_bytes,
                                           std::size_t right_bytes);

}  // namespace telesphere::link
