// SPDX-License-Identifier: MIT
/// @brief StereoFrameDecoder: receive thread, parallel decode of both images, latest-wins slot,
///        drop accounting and per-stage latency figures.
#include "xr/video/stereo_frame_decoder.h"

#include "xr/video/lost_row_concealment.h"

#include "robot/link/proto_enums.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace telesphere::xr::video {
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
    case FrameDropReason::kAwaitingKeyFrame: return "awaiting_key_frame";
    case FrameDropReason::kCount: break;
  }
  return "unknown";
}

StereoFrameDecoder::StereoFrameDecoder(link::LinkClient& client, Options options)
    : client_(client),
      options_(options),
      superseded_at_start_(client.stats().dropped(link::DropReason::kSuperseded)),
      pool_(options.threads) {
  max_in_flight_ = std::size_t(std::clamp(pool_.threads() / 2, 1, std::max(1, options_.pairs_in_flight)));
  publisher_ = std::thread([this] { publish(); });
  receiver_ = std::thread([this] { receive(); });
}

StereoFrameDecoder::~StereoFrameDecoder() {
  running_ = false;
  receiver_.join();
  {
    std::lock_guard lock(in_flight_mutex_);
    receiving_done_ = true;
  }
  in_flight_changed_.notify_all();
  publisher_.join();  // after the pairs in flight are published
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
    {
      // Room for another pair: else frames wait in the client's one-frame slot, newest wins.
      std::unique_lock lock(in_flight_mutex_);
      if (!in_flight_changed_.wait_for(lock, options_.poll, [&] { return in_flight_.size() < max_in_flight_; }))
        continue;
    }
    auto received = options_.frame_source ? options_.frame_source(options_.poll) : client_.waitForFrame(options_.poll);
    if (received) submitPair(std::move(*received));
  }
}

void StereoFrameDecoder::requestKeyFrame() {
  const std::int64_t now = link::linkNowNs();
  {
    std::lock_guard lock(key_frame_mutex_);
    if (last_key_frame_request_ns_ != 0 && now - last_key_frame_request_ns_ < kKeyFrameRequestPeriodMs * 1'000'000)
      return;
    last_key_frame_request_ns_ = now;
    ++key_frames_requested_;
    if (!key_frame_requests_)
      key_frame_requests_ = std::make_unique<link::ControlQueue>(client_, std::chrono::milliseconds(1000));
  }
  link::proto::ControlRequest request;
  request.set_request_key_frame(true);
  key_frame_requests_->send(std::move(request), [](const std::optional<link::proto::ControlReply>& reply) {
    if (reply && !reply->ok()) spdlog::warn("stereo decoder: the robot refused a key frame: {}", reply->error());
  });
}

void StereoFrameDecoder::submitPair(link::ReceivedFrame received) {
  const auto& f = received.frame;
  const auto codec = link::fromProto(f.left().codec());
  if (!codec || f.left().codec() != f.right().codec()) {
    drop(FrameDropReason::kUnsupported, f.sequence(), "both",
         "codec " + std::to_string(int(f.left().codec())) + " / " + std::to_string(int(f.right().codec())) +
             ": not one codec this build decodes");
    return;
  }
  last_codec_ = static_cast<int>(*codec);
  // H.264/HEVC: each camera's frames to its stream decoder in arrival order (one per codec).
  const bool predicted = *codec != link::VideoCodec::kMjpeg;
  if (predicted)
    for (auto& decoder : video_)
      if (!decoder || decoder->codec() != *codec) decoder = std::make_shared<VideoStreamDecoder>(*codec, 1);
  bool after_gap = false;
  const auto job = [&](int side, std::span<const std::uint8_t> bytes, const link::proto::CameraImage& image) {
    DecodeJob j;
    j.jpeg = bytes;
    j.keep_alive = received.storage;
    j.expected_width = options_.check_message_size ? static_cast<int>(image.width()) : 0;
    j.expected_height = options_.check_message_size ? static_cast<int>(image.height()) : 0;
    j.max_side = options_.max_side;
    if (!predicted) {
      j.upload_slots = options_.upload_slots;
      return j;
    }
    const VideoStreamDecoder::Turn turn = video_[side]->reserve(f.sequence());
    after_gap = turn.after_gap;
    j.decode_into = [decoder = video_[side], turn, bytes, key_frame = image.key_frame(), width = j.expected_width,
                     height = j.expected_height](render::YuvPlanes& planes, DecodeResult& result) {
      decoder->decode(turn, bytes, key_frame, width, height, planes, result);
    };
    return j;
  };
  PairInFlight pair;
  pair.left = pool_.submit(job(0, received.left_jpeg, f.left()));
  pair.right = pool_.submit(job(1, received.right_jpeg, f.right()));
  // A gap (the link or the client's latest-wins slot dropped frames, the app joined part way, the
  // robot started again): the frames after it need a key frame.
  if (after_gap && !(f.left().key_frame() && f.right().key_frame())) requestKeyFrame();
  pair.received = std::move(received);
  {
    std::lock_guard lock(in_flight_mutex_);
    in_flight_.push_back(std::move(pair));
  }
  in_flight_changed_.notify_all();
}

void StereoFrameDecoder::publish() {
  for (;;) {
    PairInFlight* oldest = nullptr;
    {
      std::unique_lock lock(in_flight_mutex_);
      in_flight_changed_.wait(lock, [&] { return !in_flight_.empty() || receiving_done_; });
      if (in_flight_.empty()) return;  // receiving done and every pair published
      oldest = &in_flight_.front();  // stays put: the receiver only appends
    }
    oldest->left.wait();
    oldest->right.wait();
    PairInFlight pair;
    {
      std::lock_guard lock(in_flight_mutex_);
      pair = std::move(in_flight_.front());
      in_flight_.pop_front();
    }
    in_flight_changed_.notify_all();
    finishPair(pair);
  }
}

void StereoFrameDecoder::finishPair(PairInFlight& pair) {
  link::ReceivedFrame& received = pair.received;
  const auto& f = received.frame;
  DecodeResult left = pair.left.get();
  DecodeResult right = pair.right.get();
  const std::int64_t decoded_ns = link::linkNowNs();
  const bool predicted = f.left().codec() != link::proto::VIDEO_CODEC_MJPEG;
  for (const auto& [result, side] : {std::pair{&left, "left"}, std::pair{&right, "right"}}) {
    if (result->error == JpegDecodeError::kNone) continue;
    // A predicted stream that lost a frame, or one that did not decode, needs a key frame.
    if (predicted) requestKeyFrame();
    drop(result->awaiting_key_frame ? FrameDropReason::kAwaitingKeyFrame : stereoDropReason(result->error),
         f.sequence(), side, result->message);
    return;
  }

  auto out = std::make_shared<DecodedStereoFrame>();
  out->frame = std::move(received.frame);
  out->frame.mutable_stamps()->set_decoded_ns(decoded_ns);
  out->left = std::move(left.planes);
  out->right = std::move(right.planes);
  if (!received.left_lost_rows.empty() || !received.right_lost_rows.empty()) {
    // Lost bands: the previous pair's rows where the link filled grey (same size only).
    std::shared_ptr<const DecodedStereoFrame> previous;
    {
      std::lock_guard lock(slot_mutex_);
      previous = slot_;
    }
    for (int i = 0; i < 2; ++i) {
      const auto& lost = i == 0 ? received.left_lost_rows : received.right_lost_rows;
      const render::YuvPlanes* before = previous ? (i == 0 ? previous->left : previous->right).get() : nullptr;
      const auto counts = concealRows(*(i == 0 ? out->left : out->right), before, lost);
      out->rows_concealed += counts.first;
      out->rows_grey += counts.second;
    }
  }
  const link::proto::StageStamps stamps = out->frame.stamps();

  // Figures first, then the hand-over, so that a reader who got this pair sees it counted.
  // Robot-side stages in the robot clock, the link crossing through the offset estimate.
  const auto offset = client_.clock().estimate();
  const auto ms = [](std::int64_t a, std::int64_t b) { return static_cast<double>(b - a) * 1e-6; };
  {
    std::lock_guard lock(stats_mutex_);
    ++decoded_;
    if (out->rows_concealed > 0) ++frames_concealed_;
    rows_concealed_ += static_cast<std::uint64_t>(out->rows_concealed);
    rows_grey_ += static_cast<std::uint64_t>(out->rows_grey);
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
  s.frames_concealed = frames_concealed_;
  s.rows_concealed = rows_concealed_;
  s.rows_grey = rows_grey_;
  s.dropped_by_reason = dropped_;
  s.codec = link::videoCodecName(static_cast<link::VideoCodec>(last_codec_.load()));
  {
    std::lock_guard key_lock(key_frame_mutex_);
    s.key_frames_requested = key_frames_requested_;
  }
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

}  // namespace telesphere::xr::video
