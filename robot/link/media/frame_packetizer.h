// SPDX-License-Identifier: MIT
/// @brief The sending half of the media path's framing (DESIGN.md §9): a stereo frame and its two
///        JPEGs become datagrams [MediaFrameMeta | left | right] in equal chunks, the meta saying
///        where each JPEG's bands lie. The chunks that hold the meta and the two JPEG headers are
///        protected by forward error correction (Reed–Solomon parity per block of chunks, by
///        default), or else sent twice (only in frames large enough that two more chunks cost
///        little): without them no band of the frame can be used.
///        packet_seq and send_us are left 0; the pacer stamps them as it sends (stampForSending).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "robot/link/media/media_packet.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link::media {

struct PacketizedFrame {
  std::uint32_t frame = 0;
  std::uint32_t frame_bytes = 0;  ///< meta and both JPEGs
  std::vector<std::vector<std::uint8_t>> datagrams;  ///< in the order to send them
  std::vector<std::uint32_t> chunk_datagram;         ///< per chunk: the datagram that carries it first
  /// H.264/HEVC (#34): each image predicted from the one before, so the sender never drops one
  /// silently; key_frame: decodable without the frames before it.
  bool predicted_codec = false, key_frame = false;
};

class FramePacketizer {
 public:
  struct Config {
    std::size_t chunk_bytes = kMaxChunkBytes;  ///< 1..kMaxChunkBytes
    /// Forward error correction: parity shards per block of up to fec_block chunks, at least one
    /// per block, fec_overhead of the block's chunks rounded up (0: none). Sent right after the
    /// block. With it the header repeats are off (the parity protects the headers too).
    double fec_overhead = 0.1;
    std::size_t fec_block = 16;  ///< 1..255
    bool repeat_headers = true;                ///< without FEC: send the meta's and the JPEG headers' chunks twice …
    std::size_t repeat_min_chunks = 20;        ///< … in frames of at least this many chunks (≤ 10 % more)
  };
  /// stream: random per sending process (newLinkInstanceId's low 32 bits, never 0).
  FramePacketizer(std::uint32_t stream, Config config);

  /// Cuts one frame; sets the images' jpeg_bytes in `frame`. False with *error when a JPEG is
  /// not a baseline JPEG whose bands can be found, or the frame exceeds kMaxMediaFrameBytes.
  bool packetize(proto::StereoFrame frame, std::span<const std::uint8_t> left_jpeg,
                 std::span<const std::uint8_t> right_jpeg, PacketizedFrame* out, std::string* error);

  std::uint32_t stream() const { return stream_; }

 private:
  std::uint32_t stream_;
  Config config_;
  std::uint32_t next_frame_ = 0;
};

/// Writes the transport fields into a datagram built by FramePacketizer, at the moment it is sent.
void stampForSending(std::vector<std::uint8_t>& datagram, std::uint32_t packet_seq, std::uint32_t send_us);

}  // namespace telesphere::link::media
