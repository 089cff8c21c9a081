// SPDX-License-Identifier: MIT
/// @brief The receiving half of the media path's framing (DESIGN.md §9): datagrams in any order,
///        duplicated, forged or truncated, become whole stereo frames or frames with lost bands
///        filled (mid grey, valid JPEG) and named by their image rows, so the operator side
///        paints them from the previous frame and counts them: a lost packet costs a band,
///        never shows as garbage. Latest wins: a frame a newer complete one overtook is dropped,
///        never repaired. A frame whose packets stopped coming for `reorder_grace_ns` is given
///        up: delivered with its lost bands filled, or counted lost when its meta or a JPEG
///        header is missing. An H.264/HEVC frame (#34) has no bands: it is delivered whole or
///        counted lost, and the decoder that misses it asks the robot for a key frame.
///        Parity shards (block_erasure_code.h) rebuild a block's lost chunks
///        as soon as enough of the block has arrived. With retransmission on (Config::repair), the
///        chunks of the newest frame that its parity cannot rebuild are asked for again
///        (takeRepairRequests, repair_request.h) once the evidence says they are lost, and the
///        frame waits for them up to 1.5 round trips — unless a newer frame completes first.
///        Memory is bounded (frames pending, bytes pending).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "robot/link/media/media_packet.h"
#include "robot/link/media/repair_request.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link::media {

/// Image rows [first, end) of one eye that hold a filler band instead of the picture.
struct LostRows {
  int first = 0, end = 0;
  bool operator==(const LostRows&) const = default;
};

struct AssembledFrame {
  std::uint32_t stream = 0, frame = 0;
  proto::StereoFrame stereo;  ///< as sent; jpeg_bytes are the assembled JPEGs' sizes
  std::vector<std::uint8_t> left_jpeg, right_jpeg;
  std::vector<LostRows> left_lost, right_lost;  ///< merged, in order; empty when whole
  std::uint32_t chunks_missing = 0;
  std::uint32_t bands_lost = 0;
  std::int64_t first_arrival_ns = 0, last_arrival_ns = 0;
  bool whole() const { return chunks_missing == 0; }
};

struct FrameAssemblerStats {
  std::uint64_t datagrams = 0;           ///< taken (placed in a frame)
  std::uint64_t frames_whole = 0;        ///< delivered with every chunk
  std::uint64_t frames_concealed = 0;    ///< delivered with filled bands
  std::uint64_t frames_lost = 0;         ///< given up without their meta or a JPEG header, or an H.264/HEVC frame with a chunk missing
  std::uint64_t video_frames_lost = 0;   ///< of those, H.264/HEVC frames (the receiver's decoder then asks for a key frame)
  std::uint64_t frames_malformed = 0;    ///< complete enough, but meta and sizes disagree
  std::uint64_t frames_superseded = 0;   ///< incomplete when a newer frame was delivered
  std::uint64_t bands_lost = 0;          ///< filled in delivered frames
  std::uint64_t parity_received = 0;     ///< parity shards taken
  std::uint64_t chunks_recovered = 0;    ///< chunks rebuilt from parity (forward error correction)
  std::uint64_t repeats_used = 0;        ///< repeated header chunks that filled a gap
  std::uint64_t repeats_unneeded = 0;    ///< repeated header chunks already held
  std::uint64_t stream_changes = 0;      ///< the sender restarted (a new stream taken over)
  std::uint64_t repair_requests = 0;     ///< repair requests made (one per frame and round)
  std::uint64_t chunks_requested = 0;    ///< chunks asked for again
  std::uint64_t chunks_repaired = 0;     ///< asked-for chunks that arrived (resent, or the original late)
  double repair_rtt_ms = 0;              ///< request → repaired chunk, smoothed (0: none yet)
  std::array<std::uint64_t, static_cast<int>(MediaDropReason::kCount)> dropped_by_reason{};
  std::uint64_t dropped(MediaDropReason r) const { return dropped_by_reason[static_cast<int>(r)]; }
};

class FrameAssembler {
 public:
  struct Config {
    std::int64_t reorder_grace_ns = 30'000'000;     ///< silence after which a frame is given up
    std::int64_t stream_switch_ns = 500'000'000;    ///< silence of the current stream before another is taken
    std::size_t max_frames_pending = 8;
    std::size_t max_bytes_pending = std::size_t{256} << 20;
    /// Retransmission: ask for what parity cannot rebuild (takeRepairRequests).
    bool repair = false;
    /// A frame silent this long (or four of its datagram spacings, if longer) has been sent whole:
    /// its missing tail is asked for (a sender that stalls mid-frame makes this a guess).
    std::int64_t repair_quiet_ns = 20'000'000;
    /// The round trip assumed until a repair has measured it; a frame waits 1.5 of it + 5 ms for
    /// its repairs, never more than repair_wait_max_ns.
    std::int64_t repair_rtt_initial_ns = 100'000'000;
    std::int64_t repair_wait_max_ns = 300'000'000;
    int repair_attempts = 2;  ///< times one chunk is asked for at most
  };
  FrameAssembler() : FrameAssembler(Config{}) {}
  explicit FrameAssembler(Config config)
      : config_(config), repair_rtt_ns_(static_cast<double>(config.repair_rtt_initial_ns)) {}

  /// Takes one datagram that arrived at arrival_ns (steady clock). Frames it completes are
  /// appended to `out`.
  void add(std::span<const std::uint8_t> datagram, std::int64_t arrival_ns, std::vector<AssembledFrame>& out);
  /// Gives up on frames silent for reorder_grace_ns (or, waiting for repairs, for the repair
  /// wait since the last request): appended to `out` with filled bands, or lost.
  void expire(std::int64_t now_ns, std::vector<AssembledFrame>& out);
  /// With Config::repair: what to ask the sender for now (at most one request, for the newest
  /// frame); `receiver` is left 0 for the caller.
  std::optional<RepairRequest> takeRepairRequest(std::int64_t now_ns);
  /// How long a frame waits for its repairs now (1.5 × the measured round trip + 5 ms).
  std::int64_t repairWaitNs() const;
  /// The path's round trip as another link measured it (the ZeroMQ link's clock sync): used
  /// until a repair has measured it here.
  void setRoundTripHintNs(std::int64_t round_trip_ns);

  const FrameAssemblerStats& stats() const { return stats_; }
  std::size_t framesPending() const { return pending_.size(); }

 private:
  /// A block of chunks with parity: its shards as they arrive.
  struct ParityBlock {
    std::uint16_t first = 0;
    std::uint8_t k = 0, r = 0;
    std::vector<std::vector<std::uint8_t>> parity;  ///< r shards (empty until arrived)
    std::vector<bool> have;
    int parity_have = 0;
  };
  struct Pending {
    MediaPacketHeader first;
    std::vector<std::uint8_t> bytes;
    std::vector<bool> have;
    std::uint32_t chunks_have = 0;
    std::int64_t first_ns = 0, last_ns = 0;
    std::vector<ParityBlock> blocks;
    // Retransmission.
    std::uint32_t highest_chunk = 0;             ///< the highest chunk index that arrived
    double spacing_ns = 0;                       ///< between its datagrams, smoothed
    std::vector<std::int64_t> requested_ns;      ///< per chunk: when last asked for (0: never)
    std::vector<std::uint8_t> requests;          ///< per chunk: how often asked for
    std::int64_t last_request_ns = 0;
  };
  /// Is `p` still waiting for chunks it asked for?
  bool awaitingRepair(const Pending& p, std::int64_t now_ns) const;
  /// Rebuilds `block`'s missing chunks when enough shards are there.
  void tryRecover(Pending& pending, ParityBlock& block);
  void drop(MediaDropReason reason) { ++stats_.dropped_by_reason[static_cast<int>(reason)]; }
  /// Delivers or counts a frame taken out of pending_; marks it and everything older done.
  void finish(Pending pending, std::vector<AssembledFrame>& out);
  void supersedeOlderThan(std::uint32_t frame);
  std::optional<AssembledFrame> build(const Pending& pending);
  std::size_t bytesPending() const;

  Config config_;
  FrameAssemblerStats stats_;
  std::uint32_t stream_ = 0;
  std::int64_t stream_last_ns_ = 0;
  std::optional<std::uint32_t> newest_done_;
  double repair_rtt_ns_;
  std::deque<Pending> pending_;  ///< oldest frame first
};

}  // namespace telesphere::link::media
