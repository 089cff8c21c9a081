// SPDX-License-Identifier: MIT
/// @brief StereoFrameDecoder: receive thread, parallel decode of both images, latest-wins slot,
///        drop accounting and per-stage latency figures.
#include "xr/stereo_frame_decoder.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace telesphere::xr {
namespace {

enum StereoSample { kDecodeMs, kCaptureEncoded, kEncodedSent, kSentReceived, kReceivedDecoded, kCaptureDecoded };

/// At most one log line per reason per this period; the lines in between are counted.
constexpr std::int64_t kStereoLogPeriodNs = 1'000'000'000;
/// fps is computed over the publications of the last this many ns.
constexpr std::int64_t kStereoFpsWindowNs = 2'000'000'000;

FrameDropReason stereoDropReason(JpegDecodeError error) {
  switch (error) {
    case JpegDecodeError::kTooLarge: return FrameDropReason::kTooLarge;
    case JpegDecodeError::kSizeMismatch: return FrameDropReason::kSizeMismatch;
    case JpegDecodeError::kUnsupported: return FrameDropReason::kUnsupported;
    case JpegDecodeError::kCorrupt:
    case JpegDecodeError::kNone: break;
  }
  return FrameDropReason::kCorrupt;
}

}  // namespace

std::string_view frameDropReasonName(FrameDropReason reason) {
  switch (reason) {
    case FrameDropReason::kSuperseded: return "superseded";
    case FrameDropReason::kCorrupt: return "corrupt";
    case FrameDropReason::kTooLarge: return "too_large";
    case FrameDropReason::kSizeMismatch: return "size_mismatch";
    case FrameDropReason::kUnsupported: return "unsupported";
    case FrameDropReason::kCount: break;
  }
  return "unknown";
}

StereoFrameDecoder::StereoFrameDecoder(link::LinkClient& client, Options options)
    : client_(client),
      options_(options),
      superseded_at_start_(client.stats().dropped(link::DropReason::kSuperseded)),
      pool_(options.threads) {
  receiver_ = std::thread([this] { receive(); });
}

StereoFrameDecoder::~StereoFrameDecoder() {
  running_ = false;
  receiver_.join();
}

std::shared_ptr<const DecodedStereoFrame> StereoFrameDecoder::newest() const {
  std::lock_guard lock(slot_mutex_);
  if (slot_) slot_read_ = true;
  return slot_;
}

std::shared_ptr<const DecodedStereoFrame> StereoFrameDecoder::waitNewer(
    std::uint64_t after_sequence, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(slot_mutex_);
  if (!published_.wait_for(lock, timeout,
                           [&] { return slot_ && slot_->frame.sequence() > after_sequence; }))
    return nullptr;
  slot_read_ = true;
  return slot_;
}

void StereoFrameDecoder::receive() {
  while (running_) {
    // Whatever arrived while the previous pair decoded has replaced its predecessors in the
    // client's one-frame slot: we always take the newest.
    if (auto received = client_.waitForFrame(options_.poll)) decodePair(std::move(*received));
  }
}

void StereoFrameDecoder::decodePair(link::ReceivedFrame received) {
  const auto& f = received.frame;
  const auto job = [&](std::span<const std::uint8_t> jpeg, const link::proto::CameraImage& image) {
    DecodeJob j;
    j.jpeg = jpeg;
    j.keep_alive = received.storage;
    j.expected_width = options_.check_message_size ? static_cast<int>(image.width()) : 0;
    j.expected_height = options_.check_message_size ? static_cast<int>(image.height()) : 0;
    j.max_side = options_.max_side;
    j.upload_slots = options_.upload_slots;
    return j;
  };
  auto left_future = pool_.submit(job(received.left_jpeg, f.left()));
  auto right_future = pool_.submit(job(received.right_jpeg, f.right()));
  DecodeResult left = left_future.get();
  DecodeResult right = right_future.get();
  const std::int64_t decoded_ns = link::linkNowNs();
  if (left.error != JpegDecodeError::kNone) {
    drop(stereoDropReason(left.error), f.sequence(), "left", left.message);
    return;
  }
  if (right.error != JpegDecodeError::kNone) {
    drop(stereoDropReason(right.error), f.sequence(), "right", right.message);
    return;
  }

  auto out = std::make_shared<DecodedStereoFrame>();
  out->frame = std::move(received.frame);
  out->frame.mutable_stamps()->set_decoded_ns(decoded_ns);
  out->left = std::move(left.planes);
  out->right = std::move(right.planes);
  const link::proto::StageStamps stamps = out->frame.stamps();

  // Figures first, then the hand-over, so that a reader who got this pair sees it counted.
  // Robot-side stages in the robot clock, the link crossing through the offset estimate.
  const auto offset = client_.clock().estimate();
  const auto ms = [](std::int64_t a, std::int64_t b) { return static_cast<double>(b - a) * 1e-6; };
  {
    std::lock_guard lock(stats_mutex_);
    ++decoded_;
    for (const DecodeResult* r : {&left, &right}) ++(r->in_upload_slot ? images_in_upload_slots_ : images_in_own_memory_);
    const auto add = [&](int which, double value) {
      auto& d = samples_ms_[static_cast<std::size_t>(which)];
      d.push_back(value);
      while (d.size() > options_.stats_window) d.pop_front();
    };
    add(kDecodeMs, left.decode_ms);
    add(kDecodeMs, right.decode_ms);
    if (stamps.capture_ns() > 0 && stamps.encoded_ns() > 0)
      add(kCaptureEncoded, ms(stamps.capture_ns(), stamps.encoded_ns()));
    if (stamps.encoded_ns() > 0 && stamps.sent_ns() > 0)
      add(kEncodedSent, ms(stamps.encoded_ns(), stamps.sent_ns()));
    if (offset && stamps.sent_ns() > 0)
      add(kSentReceived, ms(stamps.sent_ns() + offset->server_to_client_offset_ns, stamps.received_ns()));
    add(kReceivedDecoded, ms(stamps.received_ns(), decoded_ns));
    if (offset && stamps.capture_ns() > 0)
      add(kCaptureDecoded, ms(stamps.capture_ns() + offset->server_to_client_offset_ns, decoded_ns));
    publish_ns_.push_back(decoded_ns);
    while (!publish_ns_.empty() && publish_ns_.front() < decoded_ns - kStereoFpsWindowNs)
      publish_ns_.pop_front();
  }
  {
    std::lock_guard lock(slot_mutex_);
    const bool unread = slot_ && !slot_read_;
    slot_ = std::move(out);
    slot_read_ = false;
    if (unread) {
      std::lock_guard stats_lock(stats_mutex_);
      ++replaced_unread_;
    }
  }
  published_.notify_all();
}

void StereoFrameDecoder::drop(FrameDropReason reason, std::uint64_t sequence, const char* side,
                              const std::string& why) {
  const int r = static_cast<int>(reason);
  const std::int64_t now = link::linkNowNs();
  std::uint64_t count = 0, unlogged = 0;
  {
    std::lock_guard lock(stats_mutex_);
    count = ++dropped_[r];
    if (last_log_ns_[r] != 0 && now - last_log_ns_[r] < kStereoLogPeriodNs) {
      ++unlogged_[r];
      return;
    }
    last_log_ns_[r] = now;
    unlogged = std::exchange(unlogged_[r], 0);
  }
  spdlog::warn("stereo decoder: dropped frame {} ({} image): {}: {} ({} so far, {} not logged)",
               sequence, side, frameDropReasonName(reason), why, count, unlogged);
}

StereoDecodeStats StereoFrameDecoder::stats() const {
  StereoDecodeStats s;
  const std::uint64_t superseded =
      client_.stats().dropped(link::DropReason::kSuperseded) - superseded_at_start_;
  const std::int64_t now = link::linkNowNs();
  std::lock_guard lock(stats_mutex_);
  s.decoded = decoded_;
  s.replaced_unread = replaced_unread_;
  s.images_in_upload_slots = images_in_upload_slots_;
  s.images_in_own_memory = images_in_own_memory_;
  s.dropped_by_reason = dropped_;
  s.dropped_by_reason[static_cast<int>(FrameDropReason::kSuperseded)] = superseded;
  // Publications within the window before now (a stalled stream reads 0 fps).
  std::size_t recent = 0;
  std::int64_t first = 0;
  for (auto t : publish_ns_)
    if (t >= now - kStereoFpsWindowNs) {
      if (recent++ == 0) first = t;
    }
  if (recent >= 2 && publish_ns_.back() > first)
    s.fps = static_cast<double>(recent - 1) * 1e9 / static_cast<double>(publish_ns_.back() - first);
  const auto figure = [this](std::size_t i) {
    return latencyFigure(std::vector<double>(samples_ms_[i].begin(), samples_ms_[i].end()));
  };
  s.decode = figure(kDecodeMs);
  s.capture_to_encoded = figure(kCaptureEncoded);
  s.encoded_to_sent = figure(kEncodedSent);
  s.sent_to_received = figure(kSentReceived);
  s.received_to_decoded = figure(kReceivedDecoded);
  s.capture_to_decoded = figure(kCaptureDecoded);
  return s;
}

}  // namespace telesphere::xr
