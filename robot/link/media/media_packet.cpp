// SPDX-License-Identifier: MIT
/// @brief The media datagram's header: writing and checked parsing.
#include "robot/link/media/media_packet.h"

#include "robot/link/media/big_endian.h"

namespace telesphere::link::media {
using big_endian::get16;
using big_endian::get32;
using big_endian::put16;
using big_endian::put32;

std::uint32_t MediaPacketHeader::chunkPayloadBytes() const {
  if (chunk_bytes == 0) return 0;
  if (kind == MediaPacketKind::kFrameParity) return chunk_bytes;
  const std::uint64_t start = std::uint64_t{chunk_index} * chunk_bytes;
  if (start >= frame_bytes) return 0;
  const std::uint64_t left = frame_bytes - start;
  return static_cast<std::uint32_t>(left < chunk_bytes ? left : chunk_bytes);
}

std::string_view mediaDropReasonName(MediaDropReason reason) {
  switch (reason) {
    case MediaDropReason::kMalformed: return "malformed";
    case MediaDropReason::kWrongVersion: return "wrong_version";
    case MediaDropReason::kTooLarge: return "too_large";
    case MediaDropReason::kDuplicate: return "duplicate";
    case MediaDropReason::kInconsistent: return "inconsistent";
    case MediaDropReason::kLate: return "late";
    case MediaDropReason::kOtherStream: return "other_stream";
    case MediaDropReason::kCount: break;
  }
  return "unknown";
}

void writeMediaPacket(const MediaPacketHeader& h, std::span<const std::uint8_t> payload,
                      std::vector<std::uint8_t>& out) {
  out.reserve(out.size() + kMediaHeaderBytes + payload.size());
  put16(out, kMediaMagic);
  out.push_back(kMediaVersion);
  out.push_back(static_cast<std::uint8_t>(h.kind));
  out.push_back(h.flags);
  out.push_back(0);  // reserved
  put32(out, h.stream);
  put32(out, h.packet_seq);
  put32(out, h.send_us);
  put32(out, h.frame);
  put32(out, h.frame_bytes);
  put16(out, h.chunk_index);
  put16(out, h.chunk_bytes);
  put16(out, h.meta_bytes);
  if (h.kind == MediaPacketKind::kFrameParity) {
    out.push_back(h.fec_k);
    out.push_back(h.fec_r);
    out.push_back(h.fec_j);
    out.push_back(0);
  }
  out.insert(out.end(), payload.begin(), payload.end());
}

std::optional<MediaPacketView> parseMediaPacket(std::span<const std::uint8_t> d, MediaDropReason* why) {
  const auto refuse = [&](MediaDropReason r) -> std::optional<MediaPacketView> {
    *why = r;
    return std::nullopt;
  };
  if (d.size() < kMediaHeaderBytes || get16(d.data()) != kMediaMagic) return refuse(MediaDropReason::kMalformed);
  if (d[2] != kMediaVersion) return refuse(MediaDropReason::kWrongVersion);
  if (d.size() > kMaxMediaDatagramBytes) return refuse(MediaDropReason::kTooLarge);
  MediaPacketView v;
  MediaPacketHeader& h = v.header;
  if (d[3] == static_cast<std::uint8_t>(MediaPacketKind::kFrameChunk)) h.kind = MediaPacketKind::kFrameChunk;
  else if (d[3] == static_cast<std::uint8_t>(MediaPacketKind::kFrameParity)) h.kind = MediaPacketKind::kFrameParity;
  else return refuse(MediaDropReason::kMalformed);
  h.flags = d[4];
  if ((h.flags & ~MediaPacketHeader::kFlagRepeat) != 0 || d[5] != 0) return refuse(MediaDropReason::kMalformed);
  h.stream = get32(&d[6]);
  h.packet_seq = get32(&d[10]);
  h.send_us = get32(&d[14]);
  h.frame = get32(&d[18]);
  h.frame_bytes = get32(&d[22]);
  h.chunk_index = get16(&d[26]);
  h.chunk_bytes = get16(&d[28]);
  h.meta_bytes = get16(&d[30]);
  if (h.frame_bytes > kMaxMediaFrameBytes) return refuse(MediaDropReason::kTooLarge);
  if (h.frame_bytes == 0 || h.chunk_bytes == 0 || h.chunk_bytes > kMaxChunkBytes || h.meta_bytes == 0 ||
      h.meta_bytes > h.frame_bytes || h.chunk_index >= h.chunkCount() || h.chunkCount() > 65536u)
    return refuse(MediaDropReason::kMalformed);
  v.payload = d.subspan(kMediaHeaderBytes);
  if (h.kind == MediaPacketKind::kFrameParity) {
    if (v.payload.size() < kParityHeaderBytes) return refuse(MediaDropReason::kMalformed);
    h.fec_k = v.payload[0];
    h.fec_r = v.payload[1];
    h.fec_j = v.payload[2];
    if (v.payload[3] != 0 || h.flags != 0 || h.fec_k == 0 || h.fec_j >= h.fec_r || h.fec_k + h.fec_r > 255 ||
        std::uint32_t{h.chunk_index} + h.fec_k > h.chunkCount())
      return refuse(MediaDropReason::kMalformed);
    v.payload = v.payload.subspan(kParityHeaderBytes);
  }
  if (v.payload.size() != h.chunkPayloadBytes()) return refuse(MediaDropReason::kMalformed);
  return v;
}

}  // namespace telesphere::link::media
