// SPDX-License-Identifier: MIT
/// @brief The operator's end of the media path (DESIGN.md §9): says hello to the robot's
///        MediaSender, takes its datagrams, reassembles frames (FrameAssembler: lost bands
///        filled and named) and reports every datagram's arrival back every report_interval_ns,
///        which is all the sender's rate controller learns of the path; with retransmission on
///        (assembler.repair) it also asks for the chunks of the newest frame that parity cannot
///        rebuild. The newest frame waits in a one-slot hand-over (latest wins, replaced frames
///        counted). One thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "robot/link/media/media_seal.h"
#include "robot/link/media/frame_assembler.h"
#include "robot/link/media/receiver_report.h"

namespace telesphere::link::media {

struct MediaReceiverOptions {
  std::string sender_address = "127.0.0.1";  ///< a host name or an IPv4 address
  std::uint16_t sender_port = 0;
  FrameAssembler::Config assembler;
  std::int64_t report_interval_ns = 25'000'000;
  std::int64_t hello_interval_ns = 500'000'000;
  int receive_buffer_bytes = 4 << 20;  ///< SO_RCVBUF asked for (the kernel may give less)
  /// Every datagram sealed both ways (media_seal.h, a keyed link): silent until setSealKey.
  bool sealed = false;
};

struct MediaReceiverStats {
  std::uint64_t datagrams = 0, bytes = 0;
  std::uint64_t frames_delivered = 0;     ///< handed over (whole or with filled bands)
  std::uint64_t frames_replaced_unread = 0;
  std::uint64_t reports_sent = 0, hellos_sent = 0, send_errors = 0;
  std::uint64_t head_target_datagrams = 0;
  std::uint64_t unauthenticated = 0;   ///< sealed link: datagrams the session key did not open (or replays)
  std::uint64_t seal_sessions = 0;     ///< session keys given (setSealKey)
  FrameAssemblerStats assembler;
};

class MediaReceiver {
 public:
  /// Opens a socket towards the sender and starts; nothing, with the reason in *error.
  static std::unique_ptr<MediaReceiver> start(const MediaReceiverOptions& options, std::string* error);
  ~MediaReceiver();
  MediaReceiver(const MediaReceiver&) = delete;
  MediaReceiver& operator=(const MediaReceiver&) = delete;

  /// Sends `target` to the sender with the previous kHeadTargetsRepeated − 1 ones (any thread;
  /// never blocks).
  void sendHeadTarget(const proto::HeadTarget& target);
  /// The newest frame not yet taken, waiting up to `timeout` for one.
  std::optional<AssembledFrame> waitNewest(std::chrono::milliseconds timeout);
  MediaReceiverStats stats() const;
  /// A sealed link's session key, from the robot over the authenticated control channel
  /// (ControlRequest.open_media_session); any thread. A new key starts a new session.
  void setSealKey(const MediaSealKey& key);
  bool hasSealKey() const;
  /// The path's round trip as another link measured it (FrameAssembler::setRoundTripHintNs); any thread.
  void setRoundTripHintNs(std::int64_t round_trip_ns) { round_trip_hint_ns_ = round_trip_ns; }

 private:
  MediaReceiver(const MediaReceiverOptions& options, int fd);
  void run();
  void sendReports(std::int64_t now_ns);
  /// Sends `plain`, sealed on a sealed link: 1 sent, 0 the socket failed, -1 no key yet.
  int sendOut(std::span<const std::uint8_t> plain, int flags);

  MediaReceiverOptions options_;
  int fd_ = -1;
  std::uint32_t id_;
  FrameAssembler assembler_;
  std::atomic<std::int64_t> round_trip_hint_ns_{0};
  std::vector<ReportEntry> pending_entries_;
  std::uint32_t pending_stream_ = 0;
  std::int64_t last_report_ns_ = 0, last_sent_ns_ = 0;
  mutable std::mutex mutex_;
  std::deque<proto::HeadTarget> recent_targets_;  ///< under mutex_
  std::optional<MediaSealer> sealer_;  ///< sealed link, after setSealKey (under mutex_)
  std::optional<MediaOpener> opener_;
  std::condition_variable frame_ready_;
  std::optional<AssembledFrame> newest_;
  MediaReceiverStats stats_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace telesphere::link::media
