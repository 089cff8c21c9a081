// SPDX-License-Identifier: MIT
/// @brief LinkClient: a receive thread that drains frames (keeping only the newest), state and
///        control replies, and pings the server to keep the clock offset.
#include "robot/link/link_client.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <thread>
#include <zmq.hpp>

namespace telesphere::link {
namespace {

zmq::socket_t connectSocket(zmq::context_t& context, zmq::socket_type type, const LinkEndpoints& e, int offset,
                            int receive_hwm = 1000) {
  const std::string endpoint = e.connect(offset);
  zmq::socket_t socket(context, type);
  if (e.credentials.secure()) {
    socket.set(zmq::sockopt::curve_serverkey, e.credentials.robot_public_z85);
    socket.set(zmq::sockopt::curve_publickey, e.credentials.own->key.public_z85);
    socket.set(zmq::sockopt::curve_secretkey, e.credentials.own->secret_z85);
  }
  socket.set(zmq::sockopt::rcvhwm, receive_hwm);
  socket.set(zmq::sockopt::linger, 0);
  socket.set(zmq::sockopt::reconnect_ivl, 100);
  socket.set(zmq::sockopt::reconnect_ivl_max, 1000);
  if (type == zmq::socket_type::sub) socket.set(zmq::sockopt::subscribe, "");
  if (type == zmq::socket_type::push) socket.set(zmq::sockopt::sndhwm, 8);
  socket.connect(endpoint);
  return socket;
}

zmq::message_t serialise(proto::Envelope& envelope) {
  envelope.set_schema_version(kSchemaVersion);
  envelope.set_sender_clock_ns(linkNowNs());
  zmq::message_t message(envelope.ByteSizeLong());
  envelope.SerializeToArray(message.data(), static_cast<int>(message.size()));
  return message;
}

/// The three parts of a frame or preview message, kept alive together.
struct FrameParts {
  zmq::message_t envelope, left, right;
};

/// Frames: a short receive queue (latest wins anyway). State: long, for lossless telemetry.
constexpr int kFramesReceiveHwm = 8;
constexpr int kStateReceiveHwm = 20000;

}  // namespace

struct LinkClient::Impl {
  Options options;
  const std::uint64_t instance = newLinkInstanceId();
  zmq::context_t context{1};
  std::optional<zmq::socket_t> frames;
  zmq::socket_t state, uplink, control;
  zmq::socket_t handshakes;  ///< the control socket's monitor
  const LinkEndpoints endpoints;
  /// libzmq does not try again after the robot refused a key; we do, later and less often, so
  /// a key the supervisor adds to allowed/ is let in without restarting this program.
  std::int64_t retry_at_ns = 0;
  std::int64_t retry_backoff_ns = 1'000'000'000;
  std::mutex uplink_mutex;
  LinkStats stats{"link client"};
  ClockSync clock;

  std::mutex mutex;  // guards everything below
  std::condition_variable frame_arrived, reply_arrived;
  std::optional<ReceivedFrame> newest;
  std::optional<proto::RobotState> robot_state;
  std::optional<proto::XrStats> xr_stats;
  std::optional<proto::RobotHealth> robot_health;
  std::deque<proto::Envelope> telemetry;
  std::optional<ReceivedPreview> preview;
  LinkActivity activity;
  std::deque<proto::Envelope> outbox;  // control requests for the receive thread to send
  std::map<std::uint64_t, proto::ControlReply> replies;
  std::uint64_t next_id = 1;

  std::atomic<bool> running{true};
  std::thread receiver;

  Impl(const LinkEndpoints& e, Options o)
      : options(o),
        state(connectSocket(context, zmq::socket_type::sub, e, LinkEndpoints::kState, kStateReceiveHwm)),
        uplink(connectSocket(context, zmq::socket_type::push, e, LinkEndpoints::kUplink)),
        control(connectSocket(context, zmq::socket_type::dealer, e, LinkEndpoints::kControl)),
        handshakes(context, zmq::socket_type::pair),
        endpoints(e) {
    if (options.frames) frames = connectSocket(context, zmq::socket_type::sub, e, LinkEndpoints::kFrames, kFramesReceiveHwm);
    // The control channel's handshakes tell whether the robot let this key in.
    static std::atomic<int> serial{0};
    const std::string monitor = "inproc://telesphere-client-handshakes-" + std::to_string(serial++);
    zmq_socket_monitor(control.handle(), monitor.c_str(),
                       ZMQ_EVENT_HANDSHAKE_SUCCEEDED | ZMQ_EVENT_HANDSHAKE_FAILED_AUTH |
                           ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL | ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL);
    handshakes.set(zmq::sockopt::linger, 0);
    handshakes.connect(monitor);
    receiver = std::thread([this] { receive(); });
  }

  /// Connects every socket again (after the robot refused this key: it may be allowed now).
  void reconnectAll() {
    const auto again = [](zmq::socket_t& socket, const std::string& endpoint) {
      try {
        socket.disconnect(endpoint);
      } catch (const zmq::error_t&) {  // already gone after the refusal
      }
      socket.connect(endpoint);
    };
    again(state, endpoints.connect(LinkEndpoints::kState));
    again(control, endpoints.connect(LinkEndpoints::kControl));
    if (frames) again(*frames, endpoints.connect(LinkEndpoints::kFrames));
    std::lock_guard lock(uplink_mutex);
    again(uplink, endpoints.connect(LinkEndpoints::kUplink));
  }

  /// Reads the control socket's handshake events into `activity`.
  void drainHandshakes() {
    zmq::message_t event, endpoint;
    while (handshakes.recv(event, zmq::recv_flags::dontwait)) {
      if (event.more()) (void)handshakes.recv(endpoint, zmq::recv_flags::dontwait);
      if (event.size() < 6) continue;
      std::uint16_t id = 0;
      std::uint32_t value = 0;
      std::memcpy(&id, event.data(), 2);
      std::memcpy(&value, static_cast<const char*>(event.data()) + 2, 4);
      std::string why;
      bool settled = true;
      if (id == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH)
        why = value == 300 ? "the robot refused this key for now: too many handshakes (" + std::to_string(value) + ")"
                           : "the robot refused this key (status " + std::to_string(value) +
                                 "): is its .pub in the robot's allowed/ folder, with the right role?";
      else if (id == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL && value == ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH)
        why = "the robot and this program disagree on keys: one runs with --keys, the other with --insecure";
      else if (id == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL && value == ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC)
        why = "the handshake did not decrypt: the robot's .pub in --keys is not this robot's key";
      else if (id == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL || id == ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL) {
        why = "the handshake with the robot failed (" + std::to_string(value) + ")";
        settled = false;
      }
      if (id == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH && value == 300) settled = false;  // rate-limited
      if (id == ZMQ_EVENT_HANDSHAKE_SUCCEEDED) {
        retry_backoff_ns = 1'000'000'000;
        retry_at_ns = 0;
      } else if (id == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH && retry_at_ns == 0) {
        retry_at_ns = linkNowNs() + retry_backoff_ns;
        retry_backoff_ns = std::min<std::int64_t>(2 * retry_backoff_ns, 16'000'000'000);
      }
      std::lock_guard lock(mutex);
      if (id == ZMQ_EVENT_HANDSHAKE_SUCCEEDED) {
        activity.refused_reason.clear();
        activity.refusal_settled = false;
      } else if (!why.empty()) {
        ++activity.handshakes_refused;
        // A peer without keys often sees the robot hang up first (EPIPE) and the mechanism
        // mismatch only on the next attempt: the settled reason is the one to keep.
        if (settled || !activity.refusal_settled) {
          activity.refused_reason = why;
          activity.refusal_settled = settled;
        }
      }
    }
  }

  ~Impl() {
    running = false;
    receiver.join();
  }

  void receive() {
    std::int64_t next_ping_ns = 0;
    std::vector<zmq::pollitem_t> items = {{state.handle(), 0, ZMQ_POLLIN, 0},
                                          {control.handle(), 0, ZMQ_POLLIN, 0},
                                          {handshakes.handle(), 0, ZMQ_POLLIN, 0}};
    if (frames) items.push_back({frames->handle(), 0, ZMQ_POLLIN, 0});
    while (running) {
      zmq::poll(items.data(), items.size(), std::chrono::milliseconds(5));
      if (items[0].revents & ZMQ_POLLIN) drainState();
      if (items[1].revents & ZMQ_POLLIN) drainControl();
      if (items[2].revents & ZMQ_POLLIN) drainHandshakes();
      if (frames && (items[3].revents & ZMQ_POLLIN)) drainFrames();
      const std::int64_t now = linkNowNs();
      if (retry_at_ns != 0 && now >= retry_at_ns) {
        retry_at_ns = 0;
        reconnectAll();
      }
      if (now >= next_ping_ns) {
        proto::Envelope ping;
        ping.mutable_ping()->set_client_send_ns(now);
        control.send(serialise(ping), zmq::send_flags::dontwait);
        next_ping_ns = now + std::chrono::nanoseconds(options.ping_period).count();
      }
      std::deque<proto::Envelope> pending;
      {
        std::lock_guard lock(mutex);
        pending.swap(outbox);
      }
      for (auto& request : pending)
        if (control.send(serialise(request), zmq::send_flags::dontwait)) stats.countSent();
    }
  }

  /// Receives every part of one message; false when none was waiting.
  static bool receiveAll(zmq::socket_t& socket, std::vector<zmq::message_t>& parts) {
    parts.clear();
    zmq::message_t part;
    if (!socket.recv(part, zmq::recv_flags::dontwait)) return false;
    parts.push_back(std::move(part));
    while (parts.back().more()) {
      zmq::message_t next;
      if (!socket.recv(next, zmq::recv_flags::none)) break;  // parts of one message arrive together
      parts.push_back(std::move(next));
    }
    return true;
  }

  void drainFrames() {
    std::vector<zmq::message_t> parts;
    while (receiveAll(*frames, parts)) {
      const std::int64_t received_ns = linkNowNs();
      if (parts.size() != 3) {
        stats.countDrop(DropReason::kBadPartCount, "frames");
        continue;
      }
      auto envelope = stats.parse(parts[0].data(), parts[0].size(), "frames");
      if (!envelope) continue;
      if (!envelope->has_stereo_frame()) {
        stats.countDrop(DropReason::kUnexpectedBody, "frames");
        continue;
      }
      if (auto bad = checkStereoFrame(envelope->stereo_frame(), parts[1].size(), parts[2].size())) {
        stats.countDrop(*bad, "frames");
        continue;
      }
      stats.countReceived();
      auto storage = std::make_shared<FrameParts>(
          FrameParts{std::move(parts[0]), std::move(parts[1]), std::move(parts[2])});
      ReceivedFrame frame;
      frame.frame = std::move(*envelope->mutable_stereo_frame());
      frame.frame.mutable_stamps()->set_received_ns(received_ns);
      frame.left_jpeg = {static_cast<const std::uint8_t*>(storage->left.data()), storage->left.size()};
      frame.right_jpeg = {static_cast<const std::uint8_t*>(storage->right.data()), storage->right.size()};
      frame.storage = std::move(storage);
      {
        std::lock_guard lock(mutex);
        if (newest) stats.countDrop(DropReason::kSuperseded, "frames");
        newest = std::move(frame);
      }
      frame_arrived.notify_all();
    }
  }

  void drainState() {
    std::vector<zmq::message_t> parts;
    while (receiveAll(state, parts)) {
      const std::int64_t now = linkNowNs();
      if (parts.size() != 1 && parts.size() != 3) {
        stats.countDrop(DropReason::kBadPartCount, "state");
        continue;
      }
      auto envelope = stats.parse(parts[0].data(), parts[0].size(), "state");
      if (!envelope) continue;
      if (envelope->has_preview_frame() != (parts.size() == 3)) {  // only previews carry images
        stats.countDrop(DropReason::kBadPartCount, "state");
        continue;
      }
      if (envelope->has_preview_frame()) {
        takePreview(std::move(*envelope), parts, now);
        continue;
      }
      stats.countReceived();
      std::lock_guard lock(mutex);
      switch (envelope->body_case()) {
        case proto::Envelope::kRobotState:
          robot_state = std::move(*envelope->mutable_robot_state());
          activity.robot_state_ns = now;
          break;
        case proto::Envelope::kRobotHealth:
          robot_health = std::move(*envelope->mutable_robot_health());
          activity.robot_state_ns = now;
          break;
        case proto::Envelope::kXrStats:
          xr_stats = std::move(*envelope->mutable_xr_stats());
          activity.xr_ns = now;
          break;
        case proto::Envelope::kRobotTelemetry:
        case proto::Envelope::kXrTelemetry:
          (envelope->has_robot_telemetry() ? activity.robot_state_ns : activity.xr_ns) = now;
          if (!options.telemetry) break;
          if (telemetry.size() >= options.telemetry_queue) {
            telemetry.pop_front();
            ++activity.telemetry_overflow;
          }
          telemetry.push_back(std::move(*envelope));
          break;
        default:
          stats.countDrop(DropReason::kUnexpectedBody, "state");
      }
    }
  }

  void takePreview(proto::Envelope envelope, std::vector<zmq::message_t>& parts, std::int64_t now) {
    const proto::PreviewFrame& p = envelope.preview_frame();
    if (p.width() == 0 || p.height() == 0 || p.width() > kMaxImageSide || p.height() > kMaxImageSide ||
        p.left_jpeg_bytes() != parts[1].size() || p.right_jpeg_bytes() != parts[2].size()) {
      stats.countDrop(DropReason::kBadImageSize, "preview");
      return;
    }
    stats.countReceived();
    if (!options.previews) return;
    auto storage = std::make_shared<FrameParts>(
        FrameParts{std::move(parts[0]), std::move(parts[1]), std::move(parts[2])});
    ReceivedPreview out;
    out.preview = std::move(*envelope.mutable_preview_frame());
    out.left_jpeg = {static_cast<const std::uint8_t*>(storage->left.data()), storage->left.size()};
    out.right_jpeg = {static_cast<const std::uint8_t*>(storage->right.data()), storage->right.size()};
    out.storage = std::move(storage);
    std::lock_guard lock(mutex);
    preview = std::move(out);
    activity.robot_state_ns = now;
  }

  void drainControl() {
    std::vector<zmq::message_t> parts;
    while (receiveAll(control, parts)) {
      const std::int64_t now = linkNowNs();
      if (parts.size() != 1) {
        stats.countDrop(DropReason::kBadPartCount, "control");
        continue;
      }
      auto envelope = stats.parse(parts[0].data(), parts[0].size(), "control", kMaxControlReplyBytes);
      if (!envelope) continue;
      stats.countReceived();
      if (envelope->has_pong()) {
        notePong(envelope->pong(), now);
      } else if (envelope->has_control_reply()) {
        {
          std::lock_guard lock(mutex);
          replies[envelope->control_reply().id()] = envelope->control_reply();
        }
        reply_arrived.notify_all();
      } else {
        stats.countDrop(DropReason::kUnexpectedBody, "control");
      }
    }
  }

  /// A new server instance restarted its clock (maybe on another machine): start the offset
  /// estimate afresh, so no sample of the old process mixes with the new one's. The new
  /// instance is made visible only once its first sample is in.
  void notePong(const proto::Pong& pong, std::int64_t now) {
    bool restarted = false;
    {
      std::lock_guard lock(mutex);
      restarted = activity.robot_instance != 0 && pong.server_instance() != activity.robot_instance;
    }
    if (restarted) clock.reset();
    clock.addSample(pong.client_send_ns(), pong.server_ns(), now);
    std::lock_guard lock(mutex);
    activity.robot_pong_ns = now;
    if (pong.server_instance() == activity.robot_instance) return;
    if (restarted) ++activity.robot_restarts;
    activity.robot_instance = pong.server_instance();
  }

  void sendUp(proto::Envelope envelope) {
    std::lock_guard lock(uplink_mutex);
    if (uplink.send(serialise(envelope), zmq::send_flags::dontwait)) stats.countSent();
  }
};

LinkClient::LinkClient(const LinkEndpoints& endpoints, Options options)
    : impl_(std::make_unique<Impl>(endpoints, options)) {}

LinkClient::~LinkClient() = default;

std::optional<ReceivedFrame> LinkClient::takeLatestFrame() {
  std::lock_guard lock(impl_->mutex);
  std::optional<ReceivedFrame> out = std::move(impl_->newest);
  impl_->newest.reset();
  return out;
}

std::optional<ReceivedFrame> LinkClient::waitForFrame(std::chrono::milliseconds timeout) {
  std::unique_lock lock(impl_->mutex);
  impl_->frame_arrived.wait_for(lock, timeout, [&] { return impl_->newest.has_value(); });
  std::optional<ReceivedFrame> out = std::move(impl_->newest);
  impl_->newest.reset();
  return out;
}

std::optional<proto::RobotState> LinkClient::latestRobotState() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->robot_state;
}

std::optional<proto::XrStats> LinkClient::latestXrStats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->xr_stats;
}

std::uint64_t LinkClient::instance() const { return impl_->instance; }

void LinkClient::sendHeadTarget(const proto::HeadTarget& target) {
  proto::Envelope envelope;
  *envelope.mutable_head_target() = target;
  if (target.sender_instance() == 0) envelope.mutable_head_target()->set_sender_instance(impl_->instance);
  impl_->sendUp(std::move(envelope));
}

void LinkClient::sendXrStats(const proto::XrStats& stats) {
  proto::Envelope envelope;
  *envelope.mutable_xr_stats() = stats;
  impl_->sendUp(std::move(envelope));
}

std::optional<proto::ControlReply> LinkClient::request(proto::ControlRequest request,
                                                       std::chrono::milliseconds timeout) {
  std::unique_lock lock(impl_->mutex);
  const std::uint64_t id = impl_->next_id++;
  request.set_id(id);
  proto::Envelope envelope;
  *envelope.mutable_control_request() = std::move(request);
  impl_->outbox.push_back(std::move(envelope));
  if (!impl_->reply_arrived.wait_for(lock, timeout, [&] { return impl_->replies.count(id) > 0; }))
    return std::nullopt;
  proto::ControlReply reply = std::move(impl_->replies[id]);
  impl_->replies.erase(id);
  return reply;
}

std::optional<proto::RobotHealth> LinkClient::latestRobotHealth() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->robot_health;
}

std::vector<proto::Envelope> LinkClient::takeTelemetry() {
  std::lock_guard lock(impl_->mutex);
  std::vector<proto::Envelope> out(std::make_move_iterator(impl_->telemetry.begin()),
                                   std::make_move_iterator(impl_->telemetry.end()));
  impl_->telemetry.clear();
  return out;
}

std::optional<ReceivedPreview> LinkClient::takeLatestPreview() {
  std::lock_guard lock(impl_->mutex);
  std::optional<ReceivedPreview> out = std::move(impl_->preview);
  impl_->preview.reset();
  return out;
}

LinkActivity LinkClient::activity() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->activity;
}

void LinkClient::sendXrTelemetry(const proto::XrTelemetry& telemetry) {
  proto::Envelope envelope;
  *envelope.mutable_xr_telemetry() = telemetry;
  impl_->sendUp(std::move(envelope));
}

const ClockSync& LinkClient::clock() const { return impl_->clock; }

LinkStatsSnapshot LinkClient::stats() const { return impl_->stats.snapshot(); }

}  // namespace telesphere::link
