// SPDX-License-Identifier: MIT
/// @brief The operator's video path from the link to the renderer (DESIGN.md §4): a receive
///        thread takes the newest stereo frame from the LinkClient and starts decoding left and
///        right in parallel on a DecodePool; up to pairs_in_flight pairs decode at once, so a
///        pool of several threads keeps up with frames that take longer to decode than they take
///        to arrive (latest wins: frames that arrive while that many pairs decode replace each
///        other and are counted "superseded"). A publish thread takes the pairs in arrival
///        order as they finish, checks each JPEG header against the
///        message's width × height, stamps decoded_ns (client clock) and publishes the pair into a
///        one-slot, latest-wins hand-over. The renderer takes `newest()` and wraps the planes in
///        SourceImage::yuv without copying them. Bad frames (corrupt, truncated, too large,
///        mismatched, unsupported) are dropped with a counted reason and a rate-limited log line;
///        the stream resumes with the next good frame.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

#include "robot/link/control_queue.h"
#include "robot/link/link_client.h"
#include "xr/video/decode_pool.h"
#include "xr/video/video_stream_decoder.h"
#include "xr/video/latency_figure.h"

namespace telesphere::xr::video {

/// One decoded stereo pair; immutable once published, shared with every reader.
struct DecodedStereoFrame {
  link::proto::StereoFrame frame;  ///< as received, stamps.decoded_ns set (client clock)
  std::shared_ptr<const render::YuvPlanes> left, right;
  /// Rows the link lost in either image: painted from the previous frame (or left grey when there
  /// was none of that size).
  int rows_concealed = 0, rows_grey = 0;
};

/// Why a stereo frame never reached the renderer (operator side, after the link's own checks).
enum class FrameDropReason : int {
  kSuperseded,    ///< a newer frame arrived while this one waited for the decoder
  kCorrupt,       ///< corrupt or truncated JPEG data
  kTooLarge,      ///< a JPEG header beyond the side limit (refused before any allocation)
  kSizeMismatch,  ///< JPEG header size differs from the message's width × height
  kUnsupported,   ///< a chroma subsampling the renderer does not take, or a codec this build lacks
  kAwaitingKeyFrame,  ///< H.264/HEVC: a frame before it was lost; the decoder waits for a key frame
  kCount
};

std::string_view frameDropReasonName(FrameDropReason reason);

struct StereoDecodeStats {
  double fps = 0;                  ///< published pairs per second over the recent window
  std::uint64_t decoded = 0;       ///< pairs published
  std::uint64_t replaced_unread = 0;  ///< published pairs replaced before any reader got them
  std::uint64_t images_in_upload_slots = 0;  ///< images decoded straight into GL buffer memory
  std::uint64_t images_in_own_memory = 0;    ///< images decoded into the pool's memory (no free slot, or no ring)
  std::uint64_t frames_concealed = 0;        ///< pairs published with rows painted from the previous pair
  std::uint64_t rows_concealed = 0;          ///< image rows so painted (both images)
  std::uint64_t rows_grey = 0;               ///< lost rows left grey (no previous image of that size)
  /// H.264/HEVC: key frames asked of the robot (a frame lost or undecodable; at most one per
  /// kKeyFrameRequestPeriodMs), and the codec of the last frame ("mjpeg" before any).
  std::uint64_t key_frames_requested = 0;
  std::string codec = "mjpeg";
  std::array<std::uint64_t, static_cast<int>(FrameDropReason::kCount)> dropped_by_reason{};
  std::uint64_t dropped(FrameDropReason r) const { return dropped_by_reason[static_cast<int>(r)]; }
  LatencyFigure decode;               ///< one JPEG's decode on a worker
  LatencyFigure capture_to_encoded;   ///< robot clock
  LatencyFigure encoded_to_sent;      ///< robot clock
  LatencyFigure sent_to_received;     ///< robot → client clock through the ping offset estimate
  LatencyFigure received_to_decoded;  ///< client clock: waiting + decoding both images
  LatencyFigure capture_to_decoded;   ///< robot → client clock through the offset estimate
};

class StereoFrameDecoder {
 public:
  /// H.264/HEVC: key-frame requests at most this often (a lost key frame is asked for again).
  static constexpr std::int64_t kKeyFrameRequestPeriodMs = 250;

  struct Options {
    int threads = 0;  ///< decode threads; ≤ 0: hardware_concurrency
    int max_side = static_cast<int>(link::kMaxImageSide);  ///< px per side
    bool check_message_size = true;  ///< header must equal the message's width × height
    std::chrono::milliseconds poll{20};  ///< how long the receive thread waits per round
    /// Stereo pairs decoding at once (each takes two pool threads): at most this, at most half
    /// the pool's threads, at least one.
    int pairs_in_flight = 2;
    std::size_t stats_window = 512;      ///< samples kept per latency figure
    /// The renderer's upload ring: images are decoded into its GL buffer memory when a slot is
    /// free (null: always into the pool's own memory).
    std::shared_ptr<render::UploadSlotSource> upload_slots;
    /// Where frames come from (null: the LinkClient's frame channel). Waits up to the given time
    /// for the newest frame; the media path's receiver, for one.
    std::function<std::optional<link::ReceivedFrame>(std::chrono::milliseconds)> frame_source;
  };

  /// Starts the receive thread on `client`, which must outlive this object.
  StereoFrameDecoder(link::LinkClient& client, Options options);
  explicit StereoFrameDecoder(link::LinkClient& client) : StereoFrameDecoder(client, Options{}) {}
  /// Stops the receive thread (within one poll period) and the pool.
  ~StereoFrameDecoder();
  StereoFrameDecoder(const StereoFrameDecoder&) = delete;
  StereoFrameDecoder& operator=(const StereoFrameDecoder&) = delete;

  /// The newest decoded pair, or null before the first one. Never blocks on decoding.
  std::shared_ptr<const DecodedStereoFrame> newest() const;
  /// Waits up to `timeout` for a pair whose sequence is greater than after_sequence; null when
  /// none came (the sequence restarts when the robot does: then pass 0).
  std::shared_ptr<const DecodedStereoFrame> waitNewer(std::uint64_t after_sequence,
                                                      std::chrono::milliseconds timeout) const;

  StereoDecodeStats stats() const;
  const DecodePool& pool() const { return pool_; }

 private:
  struct PairInFlight {
    link::ReceivedFrame received;
    std::future<DecodeResult> left, right;
  };
  void receive();
  void submitPair(link::ReceivedFrame received);
  /// Publishes decoded pairs in the order they arrived, as each finishes.
  void publish();
  void finishPair(PairInFlight& pair);
  void drop(FrameDropReason reason, std::uint64_t sequence, const char* side, const std::string& why);
  /// Asks the robot for a key-frame pair, at most once per kKeyFrameRequestPeriodMs (any thread).
  void requestKeyFrame();

  link::LinkClient& client_;
  Options options_;
  std::uint64_t superseded_at_start_ = 0;  ///< the client's superseded count when we started

  mutable std::mutex slot_mutex_;
  mutable std::condition_variable published_;
  std::shared_ptr<const DecodedStereoFrame> slot_;
  mutable bool slot_read_ = true;

  mutable std::mutex stats_mutex_;
  std::uint64_t decoded_ = 0;
  std::uint64_t replaced_unread_ = 0;
  std::uint64_t images_in_upload_slots_ = 0, images_in_own_memory_ = 0;
  std::uint64_t frames_concealed_ = 0, rows_concealed_ = 0, rows_grey_ = 0;
  std::array<std::uint64_t, static_cast<int>(FrameDropReason::kCount)> dropped_{};
  std::array<std::int64_t, static_cast<int>(FrameDropReason::kCount)> last_log_ns_{};
  std::array<std::uint64_t, static_cast<int>(FrameDropReason::kCount)> unlogged_{};
  std::deque<std::int64_t> publish_ns_;
  std::array<std::deque<double>, 6> samples_ms_;

  mutable std::mutex key_frame_mutex_;
  std::int64_t last_key_frame_request_ns_ = 0;
  std::uint64_t key_frames_requested_ = 0;
  std::unique_ptr<link::ControlQueue> key_frame_requests_;  ///< made on the first request
  /// The receive thread's: each camera's stream decoder (null until an H.264/HEVC frame).
  std::shared_ptr<VideoStreamDecoder> video_[2];
  std::atomic<int> last_codec_{0};  ///< link::VideoCodec of the last frame submitted

  DecodePool pool_;  // after the state its workers' results feed; before the thread that uses it
  std::size_t max_in_flight_ = 1;
  std::mutex in_flight_mutex_;
  std::condition_variable in_flight_changed_;
  std::deque<PairInFlight> in_flight_;  ///< oldest first
  bool receiving_done_ = false;         ///< under in_flight_mutex_: the publisher drains and stops
  std::atomic<bool> running_{true};
  std::thread receiver_, publisher_;
};

}  // namespace telesphere::xr::video
