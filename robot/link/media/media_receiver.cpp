// SPDX-License-Identifier: MIT
/// @brief MediaReceiver: socket, reassembly, reports and the hand-over on one thread.
#include "robot/link/media/media_receiver.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "robot/link/link_endpoints.h"
#include "robot/link/link_schema.h"
#include "robot/link/media/head_target_datagram.h"

namespace telesphere::link::media {
std::unique_ptr<MediaReceiver> MediaReceiver::start(const MediaReceiverOptions& options, std::string* error) {
  if (options.sender_port == 0) {
    *error = "media receiver: no sender port";
    return nullptr;
  }
  // A name or an address, as the ZeroMQ link takes (the robot's host name works on both links).
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (const int rc = ::getaddrinfo(options.sender_address.c_str(), nullptr, &hints, &found); rc != 0 || !found) {
    *error = "media receiver: cannot resolve '" + options.sender_address + "': " + ::gai_strerror(rc);
    return nullptr;
  }
  sockaddr_in sender = *reinterpret_cast<const sockaddr_in*>(found->ai_addr);
  ::freeaddrinfo(found);
  sender.sin_port = htons(options.sender_port);
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) {
    *error = std::string("media receiver: socket: ") + std::strerror(errno);
    return nullptr;
  }
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &options.receive_buffer_bytes, sizeof options.receive_buffer_bytes);
  // Connected: only the sender's datagrams come in, and send() goes to it.
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&sender), sizeof sender) != 0) {
    *error = "media receiver: connect " + options.sender_address + ":" + std::to_string(options.sender_port) + ": " +
             std::strerror(errno);
    ::close(fd);
    return nullptr;
  }
  return std::unique_ptr<MediaReceiver>(new MediaReceiver(options, fd));
}

MediaReceiver::MediaReceiver(const MediaReceiverOptions& options, int fd)
    : options_(options),
      fd_(fd),
      id_(static_cast<std::uint32_t>(newLinkInstanceId()) | 1u),
      assembler_(options.assembler) {
  thread_ = std::thread([this] { run(); });
}

MediaReceiver::~MediaReceiver() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  ::close(fd_);
}

std::optional<AssembledFrame> MediaReceiver::waitNewest(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  frame_ready_.wait_for(lock, timeout, [&] { return newest_.has_value(); });
  std::optional<AssembledFrame> f = std::move(newest_);
  newest_.reset();
  return f;
}

void MediaReceiver::sendHeadTarget(const proto::HeadTarget& target) {
  std::vector<std::uint8_t> out;
  {
    std::lock_guard lock(mutex_);
    recent_targets_.push_back(target);
    while (recent_targets_.size() > kHeadTargetsRepeated) recent_targets_.pop_front();
    const std::vector<proto::HeadTarget> targets(recent_targets_.begin(), recent_targets_.end());
    writeHeadTargets(targets, out);
  }
  const int sent = sendOut(out, MSG_DONTWAIT);
  if (sent < 0) return;  // no session key yet: the ZeroMQ uplink carries them meanwhile
  std::lock_guard lock(mutex_);
  ++(sent > 0 ? stats_.head_target_datagrams : stats_.send_errors);
}

int MediaReceiver::sendOut(std::span<const std::uint8_t> plain, int flags) {
  if (!options_.sealed) return ::send(fd_, plain.data(), plain.size(), flags) >= 0 ? 1 : 0;
  std::vector<std::uint8_t> sealed;
  {
    std::lock_guard lock(mutex_);
    if (!sealer_) return -1;
    sealer_->seal(plain, sealed);
  }
  return ::send(fd_, sealed.data(), sealed.size(), flags) >= 0 ? 1 : 0;
}

void MediaReceiver::setSealKey(const MediaSealKey& key) {
  std::lock_guard lock(mutex_);
  sealer_.emplace(key, SealDirection::kToSender);
  opener_.emplace(key, SealDirection::kToReceiver);
  ++stats_.seal_sessions;
}

bool MediaReceiver::hasSealKey() const {
  std::lock_guard lock(mutex_);
  return sealer_.has_value();
}

MediaReceiverStats MediaReceiver::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void MediaReceiver::sendReports(std::int64_t now_ns) {
  std::vector<std::uint8_t> out;
  const auto send = [&](bool hello) {
    const int sent = sendOut(out, 0);
    if (sent < 0) return;  // no session key yet: nothing to say
    if (sent == 0) {
      std::lock_guard lock(mutex_);
      ++stats_.send_errors;
      return;
    }
    last_sent_ns_ = now_ns;
    std::lock_guard lock(mutex_);
    ++(hello ? stats_.hellos_sent : stats_.reports_sent);
  };
  std::size_t at = 0;
  while (at < pending_entries_.size()) {
    ReceiverDatagram d;
    d.stream = pending_stream_;
    d.receiver = id_;
    const std::size_t n = std::min(kMaxReportEntries, pending_entries_.size() - at);
    d.entries.assign(pending_entries_.begin() + static_cast<std::ptrdiff_t>(at),
                     pending_entries_.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
    // How long the newest entry waited here: the sender takes it out of its round trip.
    const auto waited_us = static_cast<std::uint32_t>(now_ns / 1000) - d.entries.back().arrival_us;
    d.hold_ns = static_cast<std::int64_t>(waited_us) * 1000;
    out.clear();
    writeReceiverDatagram(d, out);
    send(false);
  }
  pending_entries_.clear();
  last_report_ns_ = now_ns;
  if (last_sent_ns_ == 0 || now_ns - last_sent_ns_ >= options_.hello_interval_ns) {
    ReceiverDatagram hello;
    hello.hello = true;
    hello.stream = pending_stream_;
    hello.receiver = id_;
    out.clear();
    writeReceiverDatagram(hello, out);
    send(true);
  }
}

void MediaReceiver::run() {
  std::vector<std::uint8_t> buffer(kMaxMediaDatagramBytes + kSealOverheadBytes + 1), opened;
  std::vector<AssembledFrame> frames;
  while (!stop_) {
    const std::int64_t now_ns = linkNowNs();
    if (now_ns - last_report_ns_ >= options_.report_interval_ns) sendReports(now_ns);
    const std::int64_t wait_ns =
        std::clamp<std::int64_t>(last_report_ns_ + options_.report_interval_ns - now_ns, 0, 5'000'000);
    pollfd fd{fd_, POLLIN, 0};
    const timespec wait{0, static_cast<long>(wait_ns)};
    ::ppoll(&fd, 1, &wait, nullptr);
    frames.clear();
    while (true) {
      const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
      if (n < 0) break;  // EAGAIN, or ECONNREFUSED while nobody listens yet
      const std::int64_t arrival_ns = linkNowNs();
      std::span<const std::uint8_t> datagram(buffer.data(), static_cast<std::size_t>(n));
      if (options_.sealed) {
        // Only what the session key opens, once, reaches the parsers.
        std::lock_guard lock(mutex_);
        SealRefusal refusal{};
        if (!opener_ || !opener_->open(datagram, opened, &refusal)) {
          ++stats_.unauthenticated;
          continue;
        }
        datagram = std::span<const std::uint8_t>(opened);
      }
      MediaDropReason why{};
      if (const auto packet = parseMediaPacket(datagram, &why)) {
        if (packet->header.stream != pending_stream_ && !pending_entries_.empty()) sendReports(arrival_ns);
        pending_stream_ = packet->header.stream;
        pending_entries_.push_back({packet->header.packet_seq, static_cast<std::uint32_t>(arrival_ns / 1000)});
      }
      assembler_.add(datagram, arrival_ns, frames);
      std::lock_guard lock(mutex_);
      ++stats_.datagrams;
      stats_.bytes += static_cast<std::uint64_t>(n);  // as they came: sealed ones with their seal
    }
    if (const std::int64_t hint = round_trip_hint_ns_.exchange(0); hint > 0) assembler_.setRoundTripHintNs(hint);
    if (auto repair = assembler_.takeRepairRequest(linkNowNs())) {
      repair->receiver = id_;
      std::vector<std::uint8_t> out;
      writeRepairRequest(*repair, out);
      if (sendOut(out, 0) == 0) {
        std::lock_guard lock(mutex_);
        ++stats_.send_errors;
      }
    }
    assembler_.expire(linkNowNs(), frames);
    std::lock_guard lock(mutex_);
    stats_.assembler = assembler_.stats();
    for (AssembledFrame& f : frames) {
      if (newest_) ++stats_.frames_replaced_unread;
      newest_ = std::move(f);
      ++stats_.frames_delivered;
    }
    if (!frames.empty()) frame_ready_.notify_all();
  }
}

}  // namespace telesphere::link::media
