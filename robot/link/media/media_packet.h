// SPDX-License-Identifier: MIT
/// @brief One datagram of the media path (DESIGN.md §9): a fixed 32-byte header, big-endian,
///        then payload. A frame's payload is [MediaFrameMeta | left JPEG | right JPEG] cut into
///        chunks of equal size (the last one shorter); each packet carries one chunk and says
///        where it lies, so the receiver needs no other packet to place it.
///
///        parseMediaPacket() takes any bytes off the network: it checks every field against the
///        others and against the limits before anyone trusts them, and says why it refused.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace telesphere::link::media {

inline constexpr std::uint16_t kMediaMagic = 0x544D;  ///< "TM"
inline constexpr std::uint8_t kMediaVersion = 1;
inline constexpr std::size_t kMediaHeaderBytes = 32;
/// The largest datagram we send or accept: below a 1500-byte Ethernet MTU with IPv6 and UDP
/// headers and some tunnel overhead, so no path fragments it.
inline constexpr std::size_t kMaxMediaDatagramBytes = 1400;
/// A parity datagram carries 4 bytes more than a chunk's (its block: k, r, its index).
inline constexpr std::size_t kParityHeaderBytes = 4;
inline constexpr std::size_t kMaxChunkBytes = kMaxMediaDatagramBytes - kMediaHeaderBytes - kParityHeaderBytes;
/// Largest frame (meta and both JPEGs) a receiver reassembles: 2 × 8K 4:2:0 at quality 100 fit.
inline constexpr std::uint32_t kMaxMediaFrameBytes = 96u << 20;

enum class MediaPacketKind : std::uint8_t {
  kFrameChunk = 1,   ///< a chunk of a frame
  kFrameParity = 4,  ///< a parity shard of a block of chunks (block_erasure_code.h); 2, 3: receiver_report.h
};

struct MediaPacketHeader {
  MediaPacketKind kind = MediaPacketKind::kFrameChunk;
  std::uint8_t flags = 0;           ///< kFlagRepeat: a chunk sent again (the meta's first chunk)
  std::uint32_t stream = 0;         ///< random per sending process: a restart is a new stream
  std::uint32_t packet_seq = 0;     ///< per stream, +1 per datagram sent (loss and delay feedback)
  std::uint32_t send_us = 0;        ///< sender's steady clock in µs, wrapping (delay trend)
  std::uint32_t frame = 0;          ///< per stream, +1 per frame sent
  std::uint32_t frame_bytes = 0;    ///< the frame's payload: meta and both JPEGs
  std::uint16_t chunk_index = 0;    ///< this chunk starts at chunk_index × chunk_bytes
  std::uint16_t chunk_bytes = 0;    ///< every chunk's size but the last's
  std::uint16_t meta_bytes = 0;     ///< the MediaFrameMeta at the frame's start
  /// kFrameParity only: the block is chunks [chunk_index, chunk_index + fec_k) with fec_r parity
  /// shards; this is shard fec_j (0 ≤ j < r), chunk_bytes long.
  std::uint8_t fec_k = 0, fec_r = 0, fec_j = 0;

  static constexpr std::uint8_t kFlagRepeat = 1;

  std::uint32_t chunkCount() const { return chunk_bytes == 0 ? 0 : (frame_bytes + chunk_bytes - 1) / chunk_bytes; }
  /// The payload bytes this header's chunk must carry (a parity shard: chunk_bytes).
  std::uint32_t chunkPayloadBytes() const;
};

/// Why a datagram was not taken; counted per reason by the receiver.
enum class MediaDropReason : int {
  kMalformed,     ///< shorter than a header, wrong magic, unknown kind or flags, fields that disagree
                  ///< (a parity block past the frame's chunks, a shard index past its block's)
  kWrongVersion,  ///< another version of this format
  kTooLarge,      ///< a frame beyond kMaxMediaFrameBytes or a datagram beyond the limit
  kDuplicate,     ///< a chunk or parity shard already held
  kInconsistent,  ///< a chunk whose frame size, chunk size or meta size differ from its frame's first,
                  ///< or a parity shard whose block differs from its block's first
  kLate,          ///< a chunk of a frame already delivered, given up or superseded
  kOtherStream,   ///< a chunk of an older stream than the one being received
  kCount
};

std::string_view mediaDropReasonName(MediaDropReason reason);

/// Appends header and payload as one datagram (a parity datagram: header, k r j 0, payload).
void writeMediaPacket(const MediaPacketHeader& header, std::span<const std::uint8_t> payload,
                      std::vector<std::uint8_t>& out);

struct MediaPacketView {
  MediaPacketHeader header;
  std::span<const std::uint8_t> payload;
};

/// The header and payload of a datagram, or nothing with the reason.
std::optional<MediaPacketView> parseMediaPacket(std::span<const std::uint8_t> datagram, MediaDropReason* why);

}  // namespace telesphere::link::media
