// SPDX-License-Identifier: MIT
/// @brief The robot's end of the media path (DESIGN.md §9): a UDP socket the operator's receiver
///        says hello to; stereo frames sent to it as paced datagrams, the pace set by the
///        SendRateController from the receiver's reports. At most one JPEG frame waits while
///        another is on its way: a newer frame replaces the waiting one (counted), so no queue of
///        stale video forms here, in the kernel or, paced below the path's rate, in the network.
///        H.264/HEVC frames (#34) are each predicted from the one before, so they queue instead
///        (a few at most; the encoder's rate follows the budget, so the queue stays short). When
///        the queue would overflow, or a receiver starts listening, the chain is broken: what
///        waits is dropped, predicted frames are refused until a key frame, and the encoder is
///        asked for one (takeKeyFrameRequest) — no round trip to the receiver needed.
///        One thread; sendFrame() never blocks on the network.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>

#include "robot/link/media/frame_packetizer.h"
#include "robot/link/media/media_seal.h"
#include "robot/link/media/repair_request.h"
#include "robot/link/media/send_rate_controller.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::link::media {

struct MediaSenderOptions {
  std::string bind_address = "0.0.0.0";
  std::uint16_t port = 0;  ///< 0: any free port (see MediaSender::port)
  FramePacketizer::Config packetizer;
  SendRateOptions rate;
  /// Datagrams leave at pacing_gain × the target rate, so a frame sized for the target leaves
  /// within 1 / pacing_gain of a frame period and the path sees no burst.
  double pacing_gain = 1.25;
  /// H.264/HEVC frames that may wait behind the one being sent before the chain is broken.
  std::size_t max_video_frames_waiting = 3;
  /// A receiver silent this long is forgotten (frames wait for the next hello).
  std::int64_t receiver_timeout_ns = 3'000'000'000;
  /// Head targets that came on the media path (oldest first in each datagram), called on the
  /// sender's thread (LinkServer::offerHeadTarget on the robot); null: they are dropped.
  std::function<void(const proto::HeadTarget&)> on_head_target;
  /// Every datagram sealed both ways (media_seal.h, a keyed link): nothing is sent and nothing
  /// taken until setSealKey gives the session's key; an unsealed or forged datagram is refused.
  bool sealed = false;
};

struct MediaSenderStats {
  std::uint64_t frames_offered = 0;
  std::uint64_t frames_sent = 0;             ///< every datagram out
  std::uint64_t frames_superseded = 0;       ///< replaced while waiting by a newer one
  std::uint64_t frames_refused = 0;          ///< the packetizer refused them (not a baseline JPEG)
  std::uint64_t frames_without_receiver = 0; ///< dropped: nobody had said hello
  std::uint64_t video_frames_waiting_for_key = 0;  ///< H.264/HEVC: predicted frames refused after a broken chain
  std::uint64_t video_key_frames_asked = 0;        ///< H.264/HEVC: key frames the encoder was asked for (takeKeyFrameRequest)
  std::uint64_t datagrams_sent = 0, bytes_sent = 0, send_errors = 0;
  std::uint64_t reports_received = 0, receiver_datagrams_refused = 0, receiver_changes = 0;
  std::uint64_t head_target_datagrams = 0;
  std::uint64_t repair_requests = 0;          ///< from the receiver (repair_request.h)
  std::uint64_t repair_requests_refused = 0;  ///< for a frame superseded, gone, or past its budget
  std::uint64_t unauthenticated = 0;          ///< sealed link: datagrams not sealed with the session key, or replayed
  std::uint64_t seal_sessions = 0;            ///< session keys given (setSealKey)
  bool sealed = false;                        ///< MediaSenderOptions::sealed
  std::uint64_t chunks_resent = 0;
  double pacing_bps = 0;
  double framing_overhead = 0;  ///< recent frames' datagram bytes over their JPEG bytes, less 1
  double cap_bps = 0;           ///< the supervisor's cap (0: none)
  std::string receiver_address; ///< "host:port" of the receiver sent to; empty: none
  SendRateStats rate;
};

class MediaSender {
 public:
  /// Binds and starts; nothing, with the reason in *error (the port, errno's text).
  static std::unique_ptr<MediaSender> start(const MediaSenderOptions& options, std::string* error);
  ~MediaSender();
  MediaSender(const MediaSender&) = delete;
  MediaSender& operator=(const MediaSender&) = delete;

  std::uint16_t port() const { return port_; }
  /// Queues one frame (replacing a frame still waiting). False with *error when it cannot be
  /// cut into datagrams. Called from one thread (the video streamer's).
  bool sendFrame(const proto::StereoFrame& frame, std::span<const std::uint8_t> left_jpeg,
                 std::span<const std::uint8_t> right_jpeg, std::string* error);
  /// What the path may carry (bits/s, datagrams with their IP and UDP headers): the controller's target.
  double targetBps() const;
  /// What the encoder should aim at (bits/s of images): the target less the framing's rate
  /// (headers, meta, parity, repeated chunks per frame × frames per second) as measured on the
  /// recent frames.
  double payloadBudgetBps() const;
  /// The supervisor's cap (0: none; must be finite and ≥ 0).
  void setCapBps(double cap_bps);
  double capBps() const;
  bool hasReceiver() const;
  /// True once after this sender dropped an H.264/HEVC frame or got a new receiver: the encoder
  /// should make its next pair a key frame. Any thread.
  bool takeKeyFrameRequest();
  /// A sealed link's session key (the robot made it for the operator who asked over the
  /// authenticated control channel): from now on only datagrams sealed with it count, and every
  /// datagram out is sealed with it. The receiver so far is forgotten (a new session).
  void setSealKey(const MediaSealKey& key);
  MediaSenderStats stats() const;

 private:
  MediaSender(const MediaSenderOptions& options, int fd, int wake_fd, std::uint16_t port);
  void run();
  void readReceiver(std::int64_t now_ns);
  /// Queues the chunks a repair request asks for, if its frame is still due (under mutex_).
  void takeRepairRequest(const RepairRequest& request);
  void sendDue(std::int64_t now_ns);

  MediaSenderOptions options_;
  int fd_ = -1, wake_fd_ = -1;
  std::uint16_t port_ = 0;
  FramePacketizer packetizer_;
  mutable std::mutex mutex_;
  std::deque<PacketizedFrame> waiting_;  ///< JPEG: at most one; H.264/HEVC: up to max_video_frames_waiting
  bool video_chain_broken_ = true;       ///< H.264/HEVC: refuse predicted frames until a key frame
  bool key_frame_wanted_ = false;        ///< for takeKeyFrameRequest
  /// A new receiver, or frames dropped: what it gets next must start with a key frame (under mutex_).
  void breakVideoChain();
  std::optional<PacketizedFrame> current_;
  std::size_t next_datagram_ = 0;
  /// The frame sent last, kept for repairs while no newer one has begun.
  std::optional<PacketizedFrame> last_sent_;
  std::deque<std::vector<std::uint8_t>> repairs_;  ///< chunks asked for again: sent before anything else
  std::uint32_t repaired_frame_ = 0;
  std::size_t repaired_in_frame_ = 0;  ///< chunks resent of repaired_frame_ (at most twice its chunks)
  SendRateController rate_;
  double cap_bps_ = 0;
  double wire_per_payload_ = 1.05;  ///< datagram bytes (with IP/UDP) per JPEG byte, averaged
  double overhead_bytes_per_frame_ = 0;  ///< datagram bytes (with IP/UDP) beyond the images', averaged
  double frame_interval_ns_ = 0;         ///< between frames offered (packetized), averaged
  std::int64_t last_frame_ns_ = 0;
  MediaSenderStats stats_;
  struct Receiver;
  std::unique_ptr<Receiver> receiver_;
  std::int64_t next_send_ns_ = 0;
  std::uint32_t next_seq_ = 0;
  std::optional<MediaSealer> sealer_;  ///< sealed link, after setSealKey (under mutex_)
  std::optional<MediaOpener> opener_;
  std::vector<std::uint8_t> sealed_scratch_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace telesphere::link::media
