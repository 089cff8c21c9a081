// SPDX-License-Identifier: MIT
/// @brief FrameAssembler: placing chunks, giving up, and building JPEGs with filled bands.
#include "robot/link/media/frame_assembler.h"

#include <algorithm>
#include <string>

#include "robot/link/link_schema.h"
#include "robot/link/media/block_erasure_code.h"
#include "robot/link/media/jpeg_bands.h"

namespace telesphere::link::media {
namespace {

/// Serial-number order (RFC 1982) on 32-bit frame numbers: a is newer than b.
bool newer(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(a - b) > 0; }

/// Are all chunks that hold bytes [begin, end) of the frame present?
bool present(const std::vector<bool>& have, std::size_t chunk_bytes, std::uint64_t begin, std::uint64_t end) {
  if (begin >= end) return true;
  for (std::uint64_t i = begin / chunk_bytes; i <= (end - 1) / chunk_bytes; ++i)
    if (!have[i]) return false;
  return true;
}

void addLostRows(std::vector<LostRows>& lost, std::pair<int, int> rows) {
  if (!lost.empty() && lost.back().end >= rows.first) lost.back().end = std::max(lost.back().end, rows.second);
  else lost.push_back({rows.first, rows.second});
}

/// One eye's JPEG from the frame's bytes [offset, offset + size): copied when whole, otherwise
/// its header, its present bands and a filler for each missing one. False when its header is
/// missing or does not match the layout.
bool assembleEye(const std::vector<std::uint8_t>& bytes, const std::vector<bool>& have, std::size_t chunk_bytes,
                 std::uint64_t offset, std::uint64_t size, const proto::MediaJpegLayout& layout,
                 std::vector<std::uint8_t>& jpeg, std::vector<LostRows>& lost, std::uint32_t* bands_lost) {
  const auto* base = bytes.data() + offset;
  if (present(have, chunk_bytes, offset, offset + size)) {
    jpeg.assign(base, base + size);
    return true;
  }
  if (!present(have, chunk_bytes, offset, offset + layout.header_bytes())) return false;
  const std::span<const std::uint8_t> header(base, layout.header_bytes());
  std::string error;
  const auto geometry = readJpegBandGeometry(header, &error);
  if (!geometry || geometry->header_bytes != layout.header_bytes() ||
      geometry->bandCount() != static_cast<std::size_t>(layout.band_bytes_size()))
    return false;
  jpeg.assign(header.begin(), header.end());
  std::uint64_t at = layout.header_bytes();
  for (int b = 0; b < layout.band_bytes_size(); ++b) {
    const std::uint64_t n = layout.band_bytes(b);
    if (present(have, chunk_bytes, offset + at, offset + at + n)) {
      jpeg.insert(jpeg.end(), base + at, base + at + n);
    } else {
      if (!appendFillerBand(header, *geometry, static_cast<std::size_t>(b), jpeg, &error)) return false;
      addLostRows(lost, geometry->bandRows(static_cast<std::size_t>(b)));
      ++*bands_lost;
    }
    at += n;
  }
  if (present(have, chunk_bytes, offset + at, offset + size)) {
    jpeg.insert(jpeg.end(), base + at, base + size);
  } else {
    jpeg.push_back(0xFF);
    jpeg.push_back(0xD9);
  }
  return true;
}

std::uint64_t layoutBytes(const proto::MediaJpegLayout& layout) {
  std::uint64_t n = std::uint64_t{layout.header_bytes()} + layout.trailer_bytes();
  for (const std::uint32_t b : layout.band_bytes()) n += b;
  return n;
}

}  // namespace

std::size_t FrameAssembler::bytesPending() const {
  std::size_t n = 0;
  for (const Pending& p : pending_) n += p.bytes.size();
  return n;
}

void FrameAssembler::add(std::span<const std::uint8_t> datagram, std::int64_t arrival_ns,
                         std::vector<AssembledFrame>& out) {
  MediaDropReason why{};
  const auto packet = parseMediaPacket(datagram, &why);
  if (!packet) return drop(why);
  const MediaPacketHeader& h = packet->header;
  if (h.stream != stream_) {
    if (stream_ != 0 && arrival_ns - stream_last_ns_ < config_.stream_switch_ns) return drop(MediaDropReason::kOtherStream);
    if (stream_ != 0) ++stats_.stream_changes;
    stream_ = h.stream;
    pending_.clear();
    newest_done_.reset();
  }
  stream_last_ns_ = arrival_ns;
  if (newest_done_ && !newer(h.frame, *newest_done_)) return drop(MediaDropReason::kLate);

  auto it = std::find_if(pending_.begin(), pending_.end(), [&](const Pending& p) { return p.first.frame == h.frame; });
  if (it == pending_.end()) {
    if (h.frame_bytes > config_.max_bytes_pending) return drop(MediaDropReason::kTooLarge);
    // Room for it: give up the oldest frames first.
    while (!pending_.empty() &&
           (pending_.size() >= config_.max_frames_pending || bytesPending() + h.frame_bytes > config_.max_bytes_pending)) {
      Pending oldest = std::move(pending_.front());
      pending_.pop_front();
      finish(std::move(oldest), out);
    }
    if (newest_done_ && !newer(h.frame, *newest_done_)) return drop(MediaDropReason::kLate);
    Pending p;
    p.first = h;
    p.bytes.resize(h.frame_bytes);
    p.have.assign(h.chunkCount(), false);
    p.first_ns = arrival_ns;
    p.last_ns = arrival_ns;
    if (config_.repair) {
      p.requested_ns.assign(h.chunkCount(), 0);
      p.requests.assign(h.chunkCount(), 0);
    }
    // Keep pending_ oldest first.
    const auto at = std::find_if(pending_.begin(), pending_.end(), [&](const Pending& q) { return newer(q.first.frame, h.frame); });
    it = pending_.insert(at, std::move(p));
  }
  Pending& p = *it;
  if (h.frame_bytes != p.first.frame_bytes || h.chunk_bytes != p.first.chunk_bytes || h.meta_bytes != p.first.meta_bytes)
    return drop(MediaDropReason::kInconsistent);
  if (arrival_ns > p.last_ns) {
    const double gap = static_cast<double>(arrival_ns - p.last_ns);
    p.spacing_ns = p.spacing_ns == 0 ? gap : p.spacing_ns + (gap - p.spacing_ns) / 8.0;
  }
  if (h.kind == MediaPacketKind::kFrameParity) {
    auto block = std::find_if(p.blocks.begin(), p.blocks.end(), [&](const ParityBlock& b) { return b.first == h.chunk_index; });
    if (block == p.blocks.end()) {
      // Blocks do not overlap: one that does is forged.
      for (const ParityBlock& b : p.blocks)
        if (h.chunk_index < b.first + b.k && b.first < h.chunk_index + h.fec_k) return drop(MediaDropReason::kInconsistent);
      ParityBlock b;
      b.first = h.chunk_index;
      b.k = h.fec_k;
      b.r = h.fec_r;
      b.parity.resize(h.fec_r);
      b.have.assign(h.fec_r, false);
      p.blocks.push_back(std::move(b));
      block = p.blocks.end() - 1;
    } else if (block->k != h.fec_k || block->r != h.fec_r) {
      return drop(MediaDropReason::kInconsistent);
    }
    if (block->have[h.fec_j]) return drop(MediaDropReason::kDuplicate);
    block->parity[h.fec_j].assign(packet->payload.begin(), packet->payload.end());
    block->have[h.fec_j] = true;
    ++block->parity_have;
    ++stats_.parity_received;
    ++stats_.datagrams;
    p.last_ns = arrival_ns;
    tryRecover(p, *block);
  } else {
    const bool repeat = (h.flags & MediaPacketHeader::kFlagRepeat) != 0;
    if (p.have[h.chunk_index]) {
      if (repeat) ++stats_.repeats_unneeded;
      else drop(MediaDropReason::kDuplicate);
      return;
    }
    if (repeat) ++stats_.repeats_used;
    std::copy(packet->payload.begin(), packet->payload.end(),
              p.bytes.begin() + static_cast<std::ptrdiff_t>(std::size_t{h.chunk_index} * h.chunk_bytes));
    p.have[h.chunk_index] = true;
    ++p.chunks_have;
    p.last_ns = arrival_ns;
    p.highest_chunk = std::max<std::uint32_t>(p.highest_chunk, h.chunk_index);
    ++stats_.datagrams;
    if (!p.requested_ns.empty() && p.requested_ns[h.chunk_index] != 0) {
      // Asked for and here: a round-trip sample (the retransmission's own pacing included).
      ++stats_.chunks_repaired;
      const double sample = static_cast<double>(arrival_ns - p.requested_ns[h.chunk_index]);
      repair_rtt_ns_ = stats_.chunks_repaired == 1 ? sample : repair_rtt_ns_ + (sample - repair_rtt_ns_) / 8.0;
      stats_.repair_rtt_ms = repair_rtt_ns_ * 1e-6;
    }
    for (ParityBlock& b : p.blocks)
      if (h.chunk_index >= b.first && h.chunk_index < b.first + b.k) tryRecover(p, b);
  }
  if (p.chunks_have == p.have.size()) {
    Pending whole = std::move(p);
    pending_.erase(it);
    finish(std::move(whole), out);
  }
}

void FrameAssembler::tryRecover(Pending& p, ParityBlock& b) {
  int missing = 0;
  for (int i = 0; i < b.k; ++i) missing += !p.have[b.first + static_cast<std::size_t>(i)];
  if (missing == 0 || b.parity_have < missing) return;
  // Every shard chunk_bytes long: the frame's last chunk, when in this block, padded with zeros.
  const std::size_t size = p.first.chunk_bytes;
  std::vector<std::vector<std::uint8_t>> scratch(static_cast<std::size_t>(b.k));
  std::vector<std::uint8_t*> shards(static_cast<std::size_t>(b.k + b.r));
  std::vector<bool> present(static_cast<std::size_t>(b.k + b.r));
  for (int i = 0; i < b.k; ++i) {
    const std::size_t chunk = b.first + static_cast<std::size_t>(i);
    scratch[static_cast<std::size_t>(i)].assign(size, 0);
    const std::size_t begin = chunk * size, n = std::min(size, p.bytes.size() - begin);
    if (p.have[chunk]) std::copy_n(p.bytes.begin() + static_cast<std::ptrdiff_t>(begin), n, scratch[static_cast<std::size_t>(i)].begin());
    shards[static_cast<std::size_t>(i)] = scratch[static_cast<std::size_t>(i)].data();
    present[static_cast<std::size_t>(i)] = p.have[chunk];
  }
  for (int j = 0; j < b.r; ++j) {
    shards[static_cast<std::size_t>(b.k + j)] = b.have[static_cast<std::size_t>(j)] ? b.parity[static_cast<std::size_t>(j)].data() : nullptr;
    present[static_cast<std::size_t>(b.k + j)] = b.have[static_cast<std::size_t>(j)];
  }
  if (!BlockErasureCode(b.k, b.r).recover(shards, present, size)) return;
  for (int i = 0; i < b.k; ++i) {
    const std::size_t chunk = b.first + static_cast<std::size_t>(i);
    if (p.have[chunk]) continue;
    const std::size_t begin = chunk * size, n = std::min(size, p.bytes.size() - begin);
    std::copy_n(scratch[static_cast<std::size_t>(i)].begin(), n, p.bytes.begin() + static_cast<std::ptrdiff_t>(begin));
    p.have[chunk] = true;
    ++p.chunks_have;
    ++stats_.chunks_recovered;
  }
}

std::int64_t FrameAssembler::repairWaitNs() const {
  return std::min(static_cast<std::int64_t>(1.5 * repair_rtt_ns_) + 5'000'000, config_.repair_wait_max_ns);
}

void FrameAssembler::setRoundTripHintNs(std::int64_t round_trip_ns) {
  if (stats_.chunks_repaired == 0 && round_trip_ns > 0) repair_rtt_ns_ = static_cast<double>(round_trip_ns);
}

bool FrameAssembler::awaitingRepair(const Pending& p, std::int64_t now_ns) const {
  if (p.last_request_ns == 0 || now_ns - p.last_request_ns >= repairWaitNs()) return false;
  for (std::size_t c = 0; c < p.have.size(); ++c)
    if (!p.have[c] && p.requested_ns[c] != 0) return true;
  return false;
}

std::optional<RepairRequest> FrameAssembler::takeRepairRequest(std::int64_t now_ns) {
  if (!config_.repair || pending_.empty()) return std::nullopt;
  // Only the newest frame: an older one is superseded once the newest is done.
  Pending& p = pending_.back();
  const std::int64_t quiet_ns = std::max(config_.repair_quiet_ns, static_cast<std::int64_t>(4 * p.spacing_ns));
  const bool quiet = now_ns - p.last_ns >= quiet_ns;
  const std::int64_t wait_ns = repairWaitNs();
  // May chunk c be asked for (again) now?
  const auto askable = [&](std::size_t c) {
    return !p.have[c] && p.requests[c] < config_.repair_attempts &&
           (p.requested_ns[c] == 0 || now_ns - p.requested_ns[c] >= wait_ns);
  };
  RepairRequest request;
  request.stream = p.first.stream;
  request.frame = p.first.frame;
  std::vector<bool> in_block(p.have.size(), false);
  for (const ParityBlock& b : p.blocks) {
    const std::size_t end = std::min<std::size_t>(b.first + std::size_t{b.k}, p.have.size());
    int missing = 0, outstanding = 0;
    for (std::size_t c = b.first; c < end; ++c) {
      in_block[c] = true;
      missing += !p.have[c];
      outstanding += !p.have[c] && p.requested_ns[c] != 0 && now_ns - p.requested_ns[c] < wait_ns;
    }
    // Parity follows its block, and the next block follows the parity: a later chunk or silence
    // means every shard of this block that will come is here; a shard alone, that the rest may come.
    const bool closed = quiet || p.highest_chunk >= end;
    int need = closed ? missing - b.parity_have : b.parity_have > 0 ? missing - b.r : 0;
    need -= outstanding;
    for (std::size_t c = b.first; c < end && need > 0; ++c)
      if (askable(c)) {
        request.chunks.push_back(static_cast<std::uint16_t>(c));
        --need;
      }
  }
  // Chunks of blocks whose parity never came (or of a frame without parity): once a later chunk
  // shows they were sent — chunks leave in order, each block's parity after it, so with parity a
  // chunk's whole block must lie behind the highest chunk — or, for the frame's tail, once the
  // frame is quiet. (Silence alone also comes from a sender that stalls mid-frame.)
  std::size_t block_k = 1;
  for (const ParityBlock& b : p.blocks) block_k = std::max<std::size_t>(block_k, b.k);
  for (std::size_t c = 0; c < p.have.size(); ++c) {
    if (in_block[c] || !askable(c)) continue;
    const std::size_t block_end = p.blocks.empty() ? c + 1 : (c / block_k + 1) * block_k;
    if (quiet || p.highest_chunk >= block_end) request.chunks.push_back(static_cast<std::uint16_t>(c));
  }
  if (request.chunks.empty()) return std::nullopt;
  std::sort(request.chunks.begin(), request.chunks.end());
  if (request.chunks.size() > kMaxRepairChunks) request.chunks.resize(kMaxRepairChunks);
  for (const std::uint16_t c : request.chunks) {
    p.requested_ns[c] = now_ns;
    ++p.requests[c];
  }
  p.last_request_ns = now_ns;
  ++stats_.repair_requests;
  stats_.chunks_requested += request.chunks.size();
  return request;
}

void FrameAssembler::expire(std::int64_t now_ns, std::vector<AssembledFrame>& out) {
  // The newest silent frame decides: it is given up, everything older with it. A frame waiting
  // for its repairs is not silent until they are overdue.
  std::optional<std::size_t> newest_silent;
  for (std::size_t i = 0; i < pending_.size(); ++i)
    if (now_ns - pending_[i].last_ns >= config_.reorder_grace_ns && !awaitingRepair(pending_[i], now_ns))
      newest_silent = i;
  if (!newest_silent) return;
  Pending p = std::move(pending_[*newest_silent]);
  pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(*newest_silent));
  finish(std::move(p), out);
}

void FrameAssembler::supersedeOlderThan(std::uint32_t frame) {
  while (!pending_.empty() && newer(frame, pending_.front().first.frame)) {
    pending_.pop_front();
    ++stats_.frames_superseded;
  }
}

void FrameAssembler::finish(Pending pending, std::vector<AssembledFrame>& out) {
  const std::uint32_t frame = pending.first.frame;
  supersedeOlderThan(frame);
  if (!newest_done_ || newer(frame, *newest_done_)) newest_done_ = frame;
  std::optional<AssembledFrame> built = build(pending);
  if (!built) return;
  if (built->whole()) ++stats_.frames_whole;
  else ++stats_.frames_concealed;
  stats_.bands_lost += built->bands_lost;
  out.push_back(std::move(*built));
}

std::optional<AssembledFrame> FrameAssembler::build(const Pending& p) {
  const MediaPacketHeader& h = p.first;
  const std::size_t chunk = h.chunk_bytes;
  if (!present(p.have, chunk, 0, h.meta_bytes)) {
    ++stats_.frames_lost;
    return std::nullopt;
  }
  proto::MediaFrameMeta meta;
  const auto malformed = [&]() -> std::optional<AssembledFrame> {
    ++stats_.frames_malformed;
    return std::nullopt;
  };
  if (!meta.ParseFromArray(p.bytes.data(), h.meta_bytes)) return malformed();
  const std::uint64_t left = meta.frame().left().jpeg_bytes(), right = meta.frame().right().jpeg_bytes();
  // JPEG: the layout adds up to each image; H.264/HEVC: no layout (nothing to conceal).
  const bool jpeg = carriesJpegs(meta.frame());
  const std::uint64_t layout_left = jpeg ? left : 0, layout_right = jpeg ? right : 0;
  if (std::uint64_t{h.meta_bytes} + left + right != h.frame_bytes || layoutBytes(meta.left()) != layout_left ||
      layoutBytes(meta.right()) != layout_right || checkStereoFrame(meta.frame(), left, right))
    return malformed();
  AssembledFrame f;
  f.stream = h.stream;
  f.frame = h.frame;
  f.first_arrival_ns = p.first_ns;
  f.last_arrival_ns = p.last_ns;
  f.chunks_missing = static_cast<std::uint32_t>(p.have.size() - p.chunks_have);
  if (!jpeg && !f.whole()) {  // a predicted image with a hole would smear every image after it
    ++stats_.frames_lost;
    ++stats_.video_frames_lost;
    return std::nullopt;
  }
  if (!assembleEye(p.bytes, p.have, chunk, h.meta_bytes, left, meta.left(), f.left_jpeg, f.left_lost, &f.bands_lost) ||
      !assembleEye(p.bytes, p.have, chunk, h.meta_bytes + left, right, meta.right(), f.right_jpeg, f.right_lost,
                   &f.bands_lost)) {
    ++stats_.frames_lost;
    return std::nullopt;
  }
  f.stereo = std::move(*meta.mutable_frame());
  f.stereo.mutable_left()->set_jpeg_bytes(static_cast<std::uint32_t>(f.left_jpeg.size()));
  f.stereo.mutable_right()->set_jpeg_bytes(static_cast<std::uint32_t>(f.right_jpeg.size()));
  return f;
}

}  // namespace telesphere::link::media
