// SPDX-License-Identifier: MIT
/// @brief MediaSender: the socket, the pacer and the receiver's reports on one thread.
#include "robot/link/media/media_sender.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <netdb.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <utility>
#include <vector>

#include "robot/link/link_endpoints.h"
#include "robot/link/link_schema.h"
#include "robot/link/media/head_target_datagram.h"
#include "robot/link/media/receiver_report.h"
#include "robot/link/media/repair_request.h"

namespace telesphere::link::media {
struct MediaSender::Receiver {
  sockaddr_storage address{};
  socklen_t address_length = 0;
  std::uint32_t id = 0;
  std::int64_t last_heard_ns = 0;
  ArrivalClock arrivals;
  std::string address_text;  ///< "host:port", written when the address changes (for the statistics)
};

std::unique_ptr<MediaSender> MediaSender::start(const MediaSenderOptions& options, std::string* error) {
  if (const std::string why = checkSendRateOptions(options.rate); !why.empty()) {
    *error = "media sender: " + why;
    return nullptr;
  }
  if (!(options.pacing_gain >= 1.0)) {
    *error = "media sender: pacing_gain must be at least 1";
    return nullptr;
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(options.port);
  if (::inet_pton(AF_INET, options.bind_address.c_str(), &address.sin_addr) != 1) {
    *error = "media sender: '" + options.bind_address + "' is not an IPv4 address";
    return nullptr;
  }
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) {
    *error = std::string("media sender: socket: ") + std::strerror(errno);
    return nullptr;
  }
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    *error = "media sender: bind " + options.bind_address + ":" + std::to_string(options.port) + ": " +
             std::strerror(errno);
    ::close(fd);
    return nullptr;
  }
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length);
  const int wake_fd = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_fd < 0) {
    *error = std::string("media sender: eventfd: ") + std::strerror(errno);
    ::close(fd);
    return nullptr;
  }
  return std::unique_ptr<MediaSender>(new MediaSender(options, fd, wake_fd, ntohs(bound.sin_port)));
}

MediaSender::MediaSender(const MediaSenderOptions& options, int fd, int wake_fd, std::uint16_t port)
    : options_(options),
      fd_(fd),
      wake_fd_(wake_fd),
      port_(port),
      packetizer_(static_cast<std::uint32_t>(newLinkInstanceId()) | 1u, options.packetizer),
      rate_(options.rate) {
  stats_.rate = rate_.stats();
  thread_ = std::thread([this] { run(); });
}

MediaSender::~MediaSender() {
  stop_ = true;
  const std::uint64_t one = 1;
  (void)!::write(wake_fd_, &one, sizeof one);
  if (thread_.joinable()) thread_.join();
  ::close(fd_);
  ::close(wake_fd_);
}

bool MediaSender::sendFrame(const proto::StereoFrame& frame, std::span<const std::uint8_t> left_jpeg,
                            std::span<const std::uint8_t> right_jpeg, std::string* error) {
  {
    std::lock_guard lock(mutex_);
    ++stats_.frames_offered;
    if (!receiver_) {  // before the packetizer: cutting a 4K frame costs a copy and a scan of it
      ++stats_.frames_without_receiver;
      return true;
    }
  }
  // Cut outside the lock (a 4K frame takes milliseconds): the pacer keeps sending meanwhile.
  // Only this caller's thread uses the packetizer.
  PacketizedFrame packets;
  if (!packetizer_.packetize(frame, left_jpeg, right_jpeg, &packets, error)) {
    std::lock_guard lock(mutex_);
    ++stats_.frames_refused;
    return false;
  }
  std::lock_guard lock(mutex_);
  std::size_t wire = 0;
  const std::size_t seal_bytes = options_.sealed ? kSealOverheadBytes : 0;
  for (const auto& d : packets.datagrams) wire += d.size() + seal_bytes + 28;
  const double ratio = static_cast<double>(wire) / static_cast<double>(std::max<std::size_t>(1, left_jpeg.size() + right_jpeg.size()));
  wire_per_payload_ = 0.8 * wire_per_payload_ + 0.2 * ratio;
  // The framing's bytes per frame, and how often frames come: what the framing takes off the
  // target does not shrink with the payload (the meta, the last chunk's parity shard).
  const double overhead = static_cast<double>(wire) - static_cast<double>(left_jpeg.size() + right_jpeg.size());
  overhead_bytes_per_frame_ = overhead_bytes_per_frame_ == 0 ? overhead : 0.8 * overhead_bytes_per_frame_ + 0.2 * overhead;
  const std::int64_t now_ns = linkNowNs();
  if (last_frame_ns_ != 0) {
    const auto dt = static_cast<double>(now_ns - last_frame_ns_);
    frame_interval_ns_ = frame_interval_ns_ == 0 ? dt : 0.8 * frame_interval_ns_ + 0.2 * dt;
  }
  last_frame_ns_ = now_ns;
  if (!packets.predicted_codec) {
    stats_.frames_superseded += waiting_.size();
    waiting_.clear();
  } else if (packets.key_frame) {
    stats_.frames_superseded += waiting_.size();  // the key frame needs none of them
    waiting_.clear();
    video_chain_broken_ = false;
  } else if (video_chain_broken_) {
    ++stats_.video_frames_waiting_for_key;
    return true;
  } else if (waiting_.size() >= options_.max_video_frames_waiting) {
    breakVideoChain();
    ++stats_.video_frames_waiting_for_key;
    return true;
  }
  waiting_.push_back(std::move(packets));
  const std::uint64_t one = 1;
  (void)!::write(wake_fd_, &one, sizeof one);
  return true;
}

void MediaSender::breakVideoChain() {
  if (!waiting_.empty() && waiting_.back().predicted_codec) {  // they depend on each other: all go
    stats_.frames_superseded += waiting_.size();
    waiting_.clear();
  }
  video_chain_broken_ = true;
  key_frame_wanted_ = true;
}

bool MediaSender::takeKeyFrameRequest() {
  std::lock_guard lock(mutex_);
  if (!std::exchange(key_frame_wanted_, false)) return false;
  ++stats_.video_key_frames_asked;
  return true;
}

double MediaSender::targetBps() const {
  std::lock_guard lock(mutex_);
  return rate_.targetBps();
}

double MediaSender::payloadBudgetBps() const {
  std::lock_guard lock(mutex_);
  // The target less the framing's rate: the same budget as target / (wire per payload byte) for
  // a source that fills it, and the right one for a source that does not (H.264 of a still scene
  // makes frames of a few hundred bytes whose framing would otherwise look like most of the cost).
  if (frame_interval_ns_ <= 0) return rate_.targetBps() / wire_per_payload_;
  const double framing_bps = 8.0 * overhead_bytes_per_frame_ * 1e9 / frame_interval_ns_;
  return std::max(0.0, rate_.targetBps() - framing_bps);
}

void MediaSender::setCapBps(double cap_bps) {
  std::lock_guard lock(mutex_);
  cap_bps_ = cap_bps;
  rate_.setCapBps(cap_bps);
}

double MediaSender::capBps() const {
  std::lock_guard lock(mutex_);
  return cap_bps_;
}

void MediaSender::setSealKey(const MediaSealKey& key) {
  std::lock_guard lock(mutex_);
  sealer_.emplace(key, SealDirection::kToReceiver);
  opener_.emplace(key, SealDirection::kToSender);
  ++stats_.seal_sessions;
  receiver_.reset();
  current_.reset();
  waiting_.clear();
  last_sent_.reset();
  repairs_.clear();
  breakVideoChain();
}

bool MediaSender::hasReceiver() const {
  std::lock_guard lock(mutex_);
  return receiver_ != nullptr;
}

MediaSenderStats MediaSender::stats() const {
  std::lock_guard lock(mutex_);
  MediaSenderStats s = stats_;
  s.rate = rate_.stats();
  s.pacing_bps = options_.pacing_gain * rate_.targetBps();
  s.framing_overhead = wire_per_payload_ - 1.0;
  s.cap_bps = cap_bps_;
  s.sealed = options_.sealed;
  if (receiver_) s.receiver_address = receiver_->address_text;
  return s;
}

void MediaSender::readReceiver(std::int64_t now_ns) {
  std::vector<std::uint8_t> buffer(2048), opened;
  while (true) {
    sockaddr_storage from{};
    socklen_t length = sizeof from;
    const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &length);
    if (n < 0) return;  // EAGAIN: nothing more
    MediaDropReason why{};
    std::span<const std::uint8_t> bytes(buffer.data(), static_cast<std::size_t>(n));
    if (options_.sealed) {
      // A sealed link: only what the session key opens, once; the rest never reaches a parser.
      std::lock_guard lock(mutex_);
      SealRefusal refusal{};
      if (!opener_ || !opener_->open(bytes, opened, &refusal)) {
        ++stats_.unauthenticated;
        continue;
      }
      bytes = std::span<const std::uint8_t>(opened);
    }
    if (bytes.size() >= 4 && bytes[3] == kHeadTargetsKind) {
      // Head targets: straight on (newest by stamp is the taker's rule), not under our lock.
      const auto targets = parseHeadTargets(bytes, &why);
      {
        std::lock_guard lock(mutex_);
        ++(targets ? stats_.head_target_datagrams : stats_.receiver_datagrams_refused);
      }
      if (targets && options_.on_head_target)
        for (const proto::HeadTarget& t : *targets) options_.on_head_target(t);
      continue;
    }
    if (bytes.size() >= 4 && bytes[3] == kRepairRequestKind) {
      const auto request = parseRepairRequest(bytes, &why);
      std::lock_guard lock(mutex_);
      if (!request || !receiver_ || receiver_->id != request->receiver) {
        ++stats_.receiver_datagrams_refused;
        continue;
      }
      receiver_->last_heard_ns = now_ns;
      takeRepairRequest(*request);
      continue;
    }
    const auto datagram = parseReceiverDatagram(bytes, &why);
    std::lock_guard lock(mutex_);
    if (!datagram) {
      ++stats_.receiver_datagrams_refused;
      continue;
    }
    if (!receiver_ || receiver_->id != datagram->receiver) {
      // A new receiver (or the first): its path is new, so is what we know of it.
      if (receiver_) ++stats_.receiver_changes;
      receiver_ = std::make_unique<Receiver>();
      breakVideoChain();  // its decoder starts at a key frame
      receiver_->id = datagram->receiver;
      rate_ = SendRateController(options_.rate);
      rate_.setCapBps(cap_bps_);  // the supervisor's cap outlives any receiver
    }
    if (length != receiver_->address_length || std::memcmp(&receiver_->address, &from, length) != 0) {
      // A new address (or a receiver behind a NAT that rebinds): its text, once, not per stats().
      std::memcpy(&receiver_->address, &from, length);
      receiver_->address_length = length;
      char host[NI_MAXHOST] = {}, port[NI_MAXSERV] = {};
      receiver_->address_text = ::getnameinfo(reinterpret_cast<const sockaddr*>(&from), length, host, sizeof host, port,
                                              sizeof port, NI_NUMERICHOST | NI_NUMERICSERV) == 0
                                    ? std::string(host) + ":" + port
                                    : std::string("(unprintable address)");
    }
    receiver_->last_heard_ns = now_ns;
    if (datagram->hello || datagram->stream != packetizer_.stream()) continue;
    ++stats_.reports_received;
    std::vector<PacketReport> reports;
    reports.reserve(datagram->entries.size());
    for (const ReportEntry& e : datagram->entries) reports.push_back({e.seq, receiver_->arrivals.unwrapNs(e.arrival_us)});
    rate_.onFeedback(reports, now_ns, datagram->entries.empty() ? -1 : datagram->hold_ns);
  }
}

void MediaSender::takeRepairRequest(const RepairRequest& request) {
  ++stats_.repair_requests;
  // Due only while it is the newest frame begun: the one being sent, or the last one sent when
  // no other has begun since. A chunk not sent yet is on its way anyway.
  const PacketizedFrame* frame = nullptr;
  std::size_t sent = 0;
  if (current_) {
    if (current_->frame == request.frame) frame = &*current_, sent = next_datagram_;
  } else if (last_sent_ && last_sent_->frame == request.frame) {
    frame = &*last_sent_, sent = last_sent_->datagrams.size();
  }
  if (request.stream != packetizer_.stream() || !frame) {
    ++stats_.repair_requests_refused;
    return;
  }
  if (repaired_frame_ != request.frame) repaired_frame_ = request.frame, repaired_in_frame_ = 0;
  for (const std::uint16_t chunk : request.chunks) {
    if (chunk >= frame->chunk_datagram.size() || frame->chunk_datagram[chunk] >= sent) continue;
    if (repaired_in_frame_ >= 2 * frame->chunk_datagram.size()) {  // a receiver asking without end
      ++stats_.repair_requests_refused;
      return;
    }
    repairs_.push_back(frame->datagrams[frame->chunk_datagram[chunk]]);
    ++repaired_in_frame_;
  }
}

void MediaSender::sendDue(std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  if (receiver_ && now_ns - receiver_->last_heard_ns > options_.receiver_timeout_ns) {
    receiver_.reset();
    current_.reset();
    waiting_.clear();
    last_sent_.reset();
    repairs_.clear();
    breakVideoChain();
  }
  if (!receiver_ || (options_.sealed && !sealer_)) return;
  // No credit for idle time beyond 2 ms: a frame after a pause does not leave as one burst.
  next_send_ns_ = std::max(next_send_ns_, now_ns - 2'000'000);
  while (next_send_ns_ <= now_ns) {
    std::vector<std::uint8_t> repair;
    if (!repairs_.empty()) {
      repair = std::move(repairs_.front());
      repairs_.pop_front();
      ++stats_.chunks_resent;
    } else if (!current_ || next_datagram_ >= current_->datagrams.size()) {
      if (current_) {
        ++stats_.frames_sent;
        last_sent_ = std::move(current_);
      }
      current_.reset();
      if (waiting_.empty()) return;
      current_ = std::move(waiting_.front());
      waiting_.pop_front();
      next_datagram_ = 0;
      last_sent_.reset();  // a newer frame has begun: the last one is superseded
    }
    std::vector<std::uint8_t>& d = repair.empty() ? current_->datagrams[next_datagram_++] : repair;
    const std::uint32_t seq = next_seq_++;
    stampForSending(d, seq, static_cast<std::uint32_t>(now_ns / 1000));
    std::span<const std::uint8_t> wire(d);
    if (sealer_) {
      sealer_->seal(d, sealed_scratch_);
      wire = std::span<const std::uint8_t>(sealed_scratch_);
    }
    if (::sendto(fd_, wire.data(), wire.size(), 0, reinterpret_cast<const sockaddr*>(&receiver_->address),
                 receiver_->address_length) < 0) {
      ++stats_.send_errors;
    } else {
      ++stats_.datagrams_sent;
      stats_.bytes_sent += wire.size();
    }
    rate_.onPacketSent(seq, now_ns, wire.size() + 28);  // with the IPv4 and UDP headers
    next_send_ns_ += static_cast<std::int64_t>(8.0 * static_cast<double>(wire.size() + 28) * 1e9 /
                                               (options_.pacing_gain * rate_.targetBps()));
  }
}

void MediaSender::run() {
  while (!stop_) {
    const std::int64_t now_ns = linkNowNs();
    readReceiver(now_ns);
    sendDue(now_ns);
    std::int64_t wait_ns = 20'000'000;
    {
      std::lock_guard lock(mutex_);
      const bool has_data =
          receiver_ && ((current_ && next_datagram_ < current_->datagrams.size()) || !waiting_.empty() || !repairs_.empty());
      if (has_data) wait_ns = std::clamp<std::int64_t>(next_send_ns_ - linkNowNs(), 0, wait_ns);
    }
    pollfd fds[2] = {{fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    const timespec wait{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    ::ppoll(fds, 2, &wait, nullptr);
    if (fds[1].revents & POLLIN) {
      std::uint64_t count = 0;
      (void)!::read(wake_fd_, &count, sizeof count);
    }
  }
}

}  // namespace telesphere::link::media
