// SPDX-License-Identifier: MIT
/// @brief LinkServer: four ZeroMQ sockets and one service thread for the uplink and control.
#include "robot/link/link_server.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <zmq.hpp>

namespace telesphere::link {
namespace {

zmq::socket_t bindSocket(zmq::context_t& context, zmq::socket_type type, const std::string& endpoint,
                         int send_hwm = 1000) {
  zmq::socket_t socket(context, type);
  socket.set(zmq::sockopt::linger, 0);
  socket.set(zmq::sockopt::sndhwm, send_hwm);
  try {
    socket.bind(endpoint);
  } catch (const zmq::error_t& e) {
    throw std::runtime_error("link: cannot bind " + endpoint + ": " + e.what() +
                             " (is another telesphere-robot running?)");
  }
  return socket;
}

zmq::message_t serialise(const proto::Envelope& envelope) {
  zmq::message_t message(envelope.ByteSizeLong());
  envelope.SerializeToArray(message.data(), static_cast<int>(message.size()));
  return message;
}

/// A message that points into `bytes` and keeps it alive until ZeroMQ is done with it.
zmq::message_t zeroCopy(const SharedBytes& bytes) {
  auto* keep = new SharedBytes(bytes);
  return zmq::message_t(
      const_cast<std::uint8_t*>(bytes->data()), bytes->size(),
      [](void*, void* hint) { delete static_cast<SharedBytes*>(hint); }, keep);
}

}  // namespace

struct LinkServer::Impl {
  zmq::context_t context{1};
  std::mutex frames_mutex, state_mutex;
  zmq::socket_t frames, state, uplink, control;
  LinkStats stats{"link server"};
  mutable std::mutex head_mutex;
  std::optional<proto::HeadTarget> head_target;
  /// The newest t_ns (its own clock) of each sender instance heard, the least recently heard
  /// first; a few senders at most (restarts of the operator PC, a second one).
  std::deque<std::pair<std::uint64_t, std::int64_t>> head_senders;
  static constexpr std::size_t kMaxHeadSenders = 16;
  std::mutex handler_mutex;
  ControlHandler handler;
  const std::uint64_t instance = newLinkInstanceId();
  std::atomic<bool> running{true};
  std::thread service;
  std::mutex tap_mutex;
  std::shared_ptr<LinkTap> tap;  ///< copied under tap_mutex, called outside it

  void tell(LinkTap::Direction direction, const proto::Envelope& envelope, const SharedBytes& left = nullptr,
            const SharedBytes& right = nullptr) {
    std::shared_ptr<LinkTap> t;
    {
      std::lock_guard lock(tap_mutex);
      t = tap;
    }
    if (t) t->onLinkMessage(direction, envelope, left, right);
  }

  // A PUB past its high-water mark drops the newest message. Frames: keep the queue short, at
  // most two stereo frames (three parts each) wait per subscriber, older ones never pile up.
  // State: long enough that telemetry survives a busy subscriber (LinkServer::kStateQueueMessages).
  explicit Impl(const LinkEndpoints& e)
      : frames(bindSocket(context, zmq::socket_type::pub, e.bind(LinkEndpoints::kFrames), 6)),
        state(bindSocket(context, zmq::socket_type::pub, e.bind(LinkEndpoints::kState),
                         LinkServer::kStateQueueMessages)),
        uplink(bindSocket(context, zmq::socket_type::pull, e.bind(LinkEndpoints::kUplink))),
        control(bindSocket(context, zmq::socket_type::router, e.bind(LinkEndpoints::kControl))) {
    uplink.set(zmq::sockopt::rcvhwm, 64);
    service = std::thread([this] { serve(); });
  }

  ~Impl() {
    running = false;
    service.join();
  }

  void send(zmq::socket_t& socket, std::mutex& mutex, proto::Envelope envelope) {
    envelope.set_schema_version(kSchemaVersion);
    envelope.set_sender_clock_ns(linkNowNs());
    {
      std::lock_guard lock(mutex);
      if (socket.send(serialise(envelope), zmq::send_flags::dontwait)) stats.countSent();
    }
    tell(LinkTap::Direction::kSent, envelope);
  }

  void serve() {
    zmq::pollitem_t items[] = {{uplink.handle(), 0, ZMQ_POLLIN, 0},
                               {control.handle(), 0, ZMQ_POLLIN, 0}};
    while (running) {
      zmq::poll(items, 2, std::chrono::milliseconds(20));
      if (items[0].revents & ZMQ_POLLIN) drainUplink();
      if (items[1].revents & ZMQ_POLLIN) drainControl();
    }
  }

  void drainUplink() {
    zmq::message_t message;
    while (uplink.recv(message, zmq::recv_flags::dontwait)) {
      if (message.more()) {  // uplink messages are single-part: skip the rest of this one
        stats.countDrop(DropReason::kBadPartCount, "uplink");
        while (message.more() && uplink.recv(message, zmq::recv_flags::dontwait)) {
        }
        continue;
      }
      auto envelope = stats.parse(message.data(), message.size(), "uplink");
      if (!envelope) continue;
      stats.countReceived();
      tell(LinkTap::Direction::kReceived, *envelope);
      if (envelope->has_head_target()) {
        if (!takeHeadTarget(envelope->head_target())) stats.countDrop(DropReason::kSuperseded, "uplink");
      } else if (envelope->has_xr_stats() || envelope->has_xr_telemetry()) {
        // For the console: republished as it came, stamped with the XR app's clock inside (the
        // tap heard it as received: the republished copy is not told again).
        envelope->set_schema_version(kSchemaVersion);
        envelope->set_sender_clock_ns(linkNowNs());
        std::lock_guard lock(state_mutex);
        if (state.send(serialise(*envelope), zmq::send_flags::dontwait)) stats.countSent();
      } else {
        stats.countDrop(DropReason::kUnexpectedBody, "uplink");
      }
    }
  }

  /// Keeps `target` as the latest unless its sender already sent a newer one. Stamps are
  /// compared per sender instance only: each operator PC's clock started on its own.
  bool takeHeadTarget(const proto::HeadTarget& target) {
    std::lock_guard lock(head_mutex);
    auto sender = std::find_if(head_senders.begin(), head_senders.end(),
                               [&](const auto& s) { return s.first == target.sender_instance(); });
    if (sender != head_senders.end()) {
      if (target.t_ns() < sender->second) return false;
      head_senders.erase(sender);
    }
    head_senders.emplace_back(target.sender_instance(), target.t_ns());
    while (head_senders.size() > kMaxHeadSenders) head_senders.pop_front();
    head_target = target;
    return true;
  }

  void drainControl() {
    std::vector<zmq::message_t> parts;
    while (true) {
      parts.clear();
      zmq::message_t part;
      if (!control.recv(part, zmq::recv_flags::dontwait)) return;
      parts.push_back(std::move(part));
      while (parts.back().more()) {
        zmq::message_t next;
        if (!control.recv(next, zmq::recv_flags::dontwait)) break;
        parts.push_back(std::move(next));
      }
      // [identity, envelope] from a DEALER.
      if (parts.size() != 2) {
        stats.countDrop(DropReason::kBadPartCount, "control");
        continue;
      }
      auto envelope = stats.parse(parts[1].data(), parts[1].size(), "control");
      if (!envelope) continue;
      stats.countReceived();
      proto::Envelope reply;
      if (envelope->has_ping()) {
        reply.mutable_pong()->set_client_send_ns(envelope->ping().client_send_ns());
        reply.mutable_pong()->set_server_ns(linkNowNs());
        reply.mutable_pong()->set_server_instance(instance);
      } else if (envelope->has_control_request()) {
        tell(LinkTap::Direction::kReceived, *envelope);
        std::lock_guard lock(handler_mutex);
        if (handler) {
          *reply.mutable_control_reply() = handler(envelope->control_request());
        } else {
          reply.mutable_control_reply()->set_ok(false);
          reply.mutable_control_reply()->set_error("no handler");
        }
        reply.mutable_control_reply()->set_id(envelope->control_request().id());
      } else {
        stats.countDrop(DropReason::kUnexpectedBody, "control");
        continue;
      }
      reply.set_schema_version(kSchemaVersion);
      reply.set_sender_clock_ns(linkNowNs());
      control.send(parts[0], zmq::send_flags::sndmore | zmq::send_flags::dontwait);
      if (control.send(serialise(reply), zmq::send_flags::dontwait)) stats.countSent();
      if (reply.has_control_reply()) tell(LinkTap::Direction::kSent, reply);
    }
  }
};

LinkServer::LinkServer(const LinkEndpoints& endpoints) : impl_(std::make_unique<Impl>(endpoints)) {
  spdlog::info("link server on ports {}..{}", endpoints.base_port, endpoints.base_port + 3);
}

LinkServer::~LinkServer() = default;

std::int64_t LinkServer::publishStereoFrame(proto::StereoFrame frame, SharedBytes left_jpeg,
                                    SharedBytes right_jpeg) {
  frame.mutable_left()->set_jpeg_bytes(static_cast<std::uint32_t>(left_jpeg->size()));
  frame.mutable_right()->set_jpeg_bytes(static_cast<std::uint32_t>(right_jpeg->size()));
  proto::Envelope envelope;
  envelope.set_schema_version(kSchemaVersion);
  std::lock_guard lock(impl_->frames_mutex);
  const std::int64_t now = linkNowNs();
  frame.mutable_stamps()->set_sent_ns(now);
  envelope.set_sender_clock_ns(now);
  *envelope.mutable_stereo_frame() = std::move(frame);
  auto& socket = impl_->frames;
  // PUB never blocks: with no subscriber, or one past its high-water mark, the frame is dropped.
  if (socket.send(serialise(envelope), zmq::send_flags::sndmore | zmq::send_flags::dontwait) &&
      socket.send(zeroCopy(left_jpeg), zmq::send_flags::sndmore | zmq::send_flags::dontwait) &&
      socket.send(zeroCopy(right_jpeg), zmq::send_flags::dontwait))
    impl_->stats.countSent();
  impl_->tell(LinkTap::Direction::kSent, envelope, left_jpeg, right_jpeg);
  return now;
}

void LinkServer::publishRobotState(const proto::RobotState& state) {
  proto::Envelope envelope;
  *envelope.mutable_robot_state() = state;
  impl_->send(impl_->state, impl_->state_mutex, std::move(envelope));
}

void LinkServer::publishTelemetry(const proto::RobotTelemetry& telemetry) {
  proto::Envelope envelope;
  *envelope.mutable_robot_telemetry() = telemetry;
  impl_->send(impl_->state, impl_->state_mutex, std::move(envelope));
}

void LinkServer::publishHealth(const proto::RobotHealth& health) {
  proto::Envelope envelope;
  *envelope.mutable_robot_health() = health;
  impl_->send(impl_->state, impl_->state_mutex, std::move(envelope));
}

void LinkServer::publishPreview(proto::PreviewFrame preview, SharedBytes left_jpeg,
                                SharedBytes right_jpeg) {
  preview.set_left_jpeg_bytes(static_cast<std::uint32_t>(left_jpeg->size()));
  preview.set_right_jpeg_bytes(static_cast<std::uint32_t>(right_jpeg->size()));
  proto::Envelope envelope;
  envelope.set_schema_version(kSchemaVersion);
  envelope.set_sender_clock_ns(linkNowNs());
  *envelope.mutable_preview_frame() = std::move(preview);
  std::lock_guard lock(impl_->state_mutex);
  auto& socket = impl_->state;
  if (socket.send(serialise(envelope), zmq::send_flags::sndmore | zmq::send_flags::dontwait) &&
      socket.send(zeroCopy(left_jpeg), zmq::send_flags::sndmore | zmq::send_flags::dontwait) &&
      socket.send(zeroCopy(right_jpeg), zmq::send_flags::dontwait))
    impl_->stats.countSent();
}

std::uint64_t LinkServer::instance() const { return impl_->instance; }

bool LinkServer::offerHeadTarget(const proto::HeadTarget& target) { return impl_->takeHeadTarget(target); }

std::optional<proto::HeadTarget> LinkServer::latestHeadTarget() const {
  std::lock_guard lock(impl_->head_mutex);
  return impl_->head_target;
}

void LinkServer::setControlHandler(ControlHandler handler) {
  std::lock_guard lock(impl_->handler_mutex);
  impl_->handler = std::move(handler);
}

void LinkServer::setTap(std::shared_ptr<LinkTap> tap) {
  std::lock_guard lock(impl_->tap_mutex);
  impl_->tap = std::move(tap);
}

LinkStatsSnapshot LinkServer::stats() const { return impl_->stats.snapshot(); }

}  // namespace telesphere::link
