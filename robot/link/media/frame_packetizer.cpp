// SPDX-License-Identifier: MIT
/// @brief FramePacketizer: meta, chunks, the repeated header chunks.
#include "robot/link/media/frame_packetizer.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "robot/link/link_schema.h"
#include "robot/link/media/block_erasure_code.h"
#include "robot/link/media/jpeg_bands.h"

namespace telesphere::link::media {
namespace {

bool layoutOf(std::span<const std::uint8_t> jpeg, const char* eye, proto::MediaJpegLayout* layout, std::string* error) {
  std::string why;
  const auto bands = findJpegBands(jpeg, &why);
  if (!bands) {
    *error = std::string(eye) + " JPEG: " + why;
    return false;
  }
  layout->set_header_bytes(bands->header_bytes);
  for (const std::uint32_t b : bands->band_bytes) layout->add_band_bytes(b);
  layout->set_trailer_bytes(bands->trailer_bytes);
  return true;
}

}  // namespace

FramePacketizer::FramePacketizer(std::uint32_t stream, Config config) : stream_(stream), config_(config) {
  if (stream_ == 0) throw std::invalid_argument("FramePacketizer: stream 0 is not a stream");
  if (config_.chunk_bytes < 1 || config_.chunk_bytes > kMaxChunkBytes)
    throw std::invalid_argument("FramePacketizer: chunk_bytes " + std::to_string(config_.chunk_bytes) +
                                " outside 1.." + std::to_string(kMaxChunkBytes));
  if (!(config_.fec_overhead >= 0 && config_.fec_overhead <= 1) || config_.fec_block < 1 || config_.fec_block > 200)
    throw std::invalid_argument("FramePacketizer: fec_overhead must be in [0, 1] and fec_block in 1..200");
}

bool FramePacketizer::packetize(proto::StereoFrame frame, std::span<const std::uint8_t> left_jpeg,
                                std::span<const std::uint8_t> right_jpeg, PacketizedFrame* out,
                                std::string* error) {
  proto::MediaFrameMeta meta;
  frame.mutable_left()->set_jpeg_bytes(static_cast<std::uint32_t>(left_jpeg.size()));
  frame.mutable_right()->set_jpeg_bytes(static_cast<std::uint32_t>(right_jpeg.size()));
  *meta.mutable_frame() = std::move(frame);
  // An H.264/HEVC access unit has no bands to conceal (a frame comes whole or not at all): its
  // layout stays empty and the repeats cover the meta alone.
  const bool jpeg = carriesJpegs(meta.frame());
  if (jpeg && (!layoutOf(left_jpeg, "left", meta.mutable_left(), error) ||
               !layoutOf(right_jpeg, "right", meta.mutable_right(), error)))
    return false;
  const std::string meta_bytes = meta.SerializeAsString();
  const std::uint64_t total = meta_bytes.size() + left_jpeg.size() + right_jpeg.size();
  const std::uint64_t chunks = (total + config_.chunk_bytes - 1) / config_.chunk_bytes;
  if (meta_bytes.size() > 0xFFFF || total > kMaxMediaFrameBytes || chunks > 65536) {
    *error = "a frame of " + std::to_string(total) + " bytes (meta " + std::to_string(meta_bytes.size()) +
             ") is beyond the media path's limits";
    return false;
  }
  // The payload [meta | left | right] is never joined: each chunk copies its bytes straight from
  // the three pieces into its datagram (one copy of the frame), and the parity reads the chunks
  // from their datagrams.
  const std::span<const std::uint8_t> pieces[3] = {
      {reinterpret_cast<const std::uint8_t*>(meta_bytes.data()), meta_bytes.size()}, left_jpeg, right_jpeg};
  const auto copyPayload = [&](std::uint64_t begin, std::uint64_t n, std::uint8_t* to) {
    for (const auto& piece : pieces) {
      if (n == 0) return;
      if (begin >= piece.size()) {
        begin -= piece.size();
        continue;
      }
      const std::uint64_t take = std::min<std::uint64_t>(n, piece.size() - begin);
      std::copy_n(piece.data() + begin, take, to);
      to += take;
      n -= take;
      begin = 0;
    }
  };

  MediaPacketHeader h;
  h.stream = stream_;
  h.frame = next_frame_++;
  h.frame_bytes = static_cast<std::uint32_t>(total);
  h.chunk_bytes = static_cast<std::uint16_t>(config_.chunk_bytes);
  h.meta_bytes = static_cast<std::uint16_t>(meta_bytes.size());
  out->frame = h.frame;
  out->frame_bytes = h.frame_bytes;
  out->predicted_codec = !jpeg;
  out->key_frame = !jpeg && meta.frame().left().key_frame() && meta.frame().right().key_frame();
  out->datagrams.clear();
  out->chunk_datagram.assign(chunks, 0);
  out->datagrams.reserve(static_cast<std::size_t>(static_cast<double>(chunks) * (1.0 + config_.fec_overhead)) + 8);
  const auto chunkAt = [&](std::uint64_t index, std::uint8_t flags) {
    MediaPacketHeader c = h;
    c.chunk_index = static_cast<std::uint16_t>(index);
    c.flags = flags;
    const std::uint64_t begin = index * config_.chunk_bytes;
    const std::uint64_t n = std::min<std::uint64_t>(total - begin, config_.chunk_bytes);
    std::vector<std::uint8_t> datagram;
    writeMediaPacket(c, {}, datagram);
    datagram.resize(kMediaHeaderBytes + n);
    copyPayload(begin, n, datagram.data() + kMediaHeaderBytes);
    if (flags == 0) out->chunk_datagram[index] = static_cast<std::uint32_t>(out->datagrams.size());
    out->datagrams.push_back(std::move(datagram));
  };
  const bool fec = config_.fec_overhead > 0;
  const std::size_t size = config_.chunk_bytes;
  std::vector<std::uint8_t> last_padded;            // the frame's last chunk, padded to `size`
  std::optional<BlockErasureCode> code;             // full blocks share one; the last may differ
  for (std::uint64_t first = 0; first < chunks; first += fec ? config_.fec_block : chunks) {
    const std::uint64_t k = fec ? std::min<std::uint64_t>(config_.fec_block, chunks - first) : chunks - first;
    const std::size_t block_datagrams = out->datagrams.size();
    for (std::uint64_t i = first; i < first + k; ++i) chunkAt(i, 0);
    if (!fec) continue;
    const int r = std::max(1, static_cast<int>(std::ceil(config_.fec_overhead * static_cast<double>(k))));
    std::vector<const std::uint8_t*> data(k);
    for (std::uint64_t i = 0; i < k; ++i) {
      const std::vector<std::uint8_t>& d = out->datagrams[block_datagrams + i];
      data[i] = d.data() + kMediaHeaderBytes;
      if (d.size() - kMediaHeaderBytes < size) {  // only the frame's last chunk is short
        last_padded.assign(size, 0);
        std::copy(d.begin() + static_cast<std::ptrdiff_t>(kMediaHeaderBytes), d.end(), last_padded.begin());
        data[i] = last_padded.data();
      }
    }
    if (!code || code->dataShards() != static_cast<int>(k) || code->parityShards() != r)
      code.emplace(static_cast<int>(k), r);
    std::vector<std::vector<std::uint8_t>> parity(static_cast<std::size_t>(r), std::vector<std::uint8_t>(size));
    std::vector<std::uint8_t*> shards;
    for (auto& p : parity) shards.push_back(p.data());
    code->encode(data, shards, size);
    for (int j = 0; j < r; ++j) {
      MediaPacketHeader c = h;
      c.kind = MediaPacketKind::kFrameParity;
      c.chunk_index = static_cast<std::uint16_t>(first);
      c.fec_k = static_cast<std::uint8_t>(k);
      c.fec_r = static_cast<std::uint8_t>(r);
      c.fec_j = static_cast<std::uint8_t>(j);
      std::vector<std::uint8_t> datagram;
      writeMediaPacket(c, parity[static_cast<std::size_t>(j)], datagram);
      out->datagrams.push_back(std::move(datagram));
    }
  }
  if (!fec && config_.repeat_headers && chunks >= config_.repeat_min_chunks) {
    // The chunks holding [0, meta + left header) and the right header, once more at the end.
    const std::uint64_t right_start = meta_bytes.size() + left_jpeg.size();
    const std::uint64_t first_end = meta_bytes.size() + meta.left().header_bytes();
    std::vector<std::uint64_t> repeat;
    for (std::uint64_t i = 0; i * config_.chunk_bytes < first_end; ++i) repeat.push_back(i);
    for (std::uint64_t i = right_start / config_.chunk_bytes;
         i * config_.chunk_bytes < right_start + meta.right().header_bytes(); ++i)
      if (repeat.empty() || repeat.back() < i) repeat.push_back(i);
    for (const std::uint64_t i : repeat) chunkAt(i, MediaPacketHeader::kFlagRepeat);
  }
  return true;
}

void stampForSending(std::vector<std::uint8_t>& d, std::uint32_t packet_seq, std::uint32_t send_us) {
  if (d.size() < kMediaHeaderBytes) return;
  for (int i = 0; i < 4; ++i) {
    d[10 + i] = static_cast<std::uint8_t>(packet_seq >> (24 - 8 * i));
    d[14 + i] = static_cast<std::uint8_t>(send_us >> (24 - 8 * i));
  }
}

}  // namespace telesphere::link::media
