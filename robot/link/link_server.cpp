// SPDX-License-Identifier: MIT
/// @brief LinkServer: four ZeroMQ sockets and one service thread for the uplink and control.
#include "robot/link/link_server.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <zmq.hpp>

#include "robot/link/trust/allowed_keys.h"
#include "robot/link/trust/handshake_monitor.h"
#include "robot/link/trust/link_refusals.h"
#include "robot/link/trust/operator_seat.h"
#include "robot/link/trust/token_bucket.h"
#include "robot/link/trust/zap_authenticator.h"

namespace telesphere::link {
namespace {

/// The ZAP domain of each channel (ZapAuthenticator): which roles may connect to it.
/// Frames are the full-rate view: operators and supervisors; viewers get previews on the
/// state channel. Uplink and control admit every role at the handshake (the console's client
/// always connects them); what a role may send there is checked per message.
bool roleMayConnect(const std::string& domain, trust::LinkRole role) {
  if (domain == "frames") return role == trust::LinkRole::kOperator || role == trust::LinkRole::kSupervisor;
  return domain == "state" || domain == "uplink" || domain == "control";
}

zmq::socket_t bindSocket(zmq::context_t& context, zmq::socket_type type, const LinkEndpoints& e, int offset,
                         const char* domain, int send_hwm = 1000) {
  const std::string endpoint = e.bind(offset);
  zmq::socket_t socket(context, type);
  socket.set(zmq::sockopt::linger, 0);
  socket.set(zmq::sockopt::sndhwm, send_hwm);
  // A peer that opens a connection and never finishes the handshake (slow loris) is closed.
  socket.set(zmq::sockopt::handshake_ivl, 5000);
  // Nothing a client may send is larger than an apply_calibration request (control) or a
  // subscription (PUB sockets: their clients send only those and handshake commands); a frame
  // claiming more closes its connection before any memory is taken for it. Without a limit
  // libzmq tries to allocate whatever a frame header claims (2^63 bytes from a hostile peer).
  socket.set(zmq::sockopt::maxmsgsize, type == zmq::socket_type::pub ? std::int64_t(64) << 10 : std::int64_t(16) << 20);
  if (e.credentials.secure()) {
    socket.set(zmq::sockopt::curve_server, 1);
    socket.set(zmq::sockopt::curve_secretkey, e.credentials.own->secret_z85);
    socket.set(zmq::sockopt::zap_domain, domain);
  }
  try {
    socket.bind(endpoint);
  } catch (const zmq::error_t& err) {
    throw std::runtime_error("link: cannot bind " + endpoint + ": " + err.what() +
                             " (is another telesphere-robot running?)");
  }
  return socket;
}

/// What each role may ask on the control channel (DESIGN.md §10): pings from anyone; an
/// operator what its own view needs, a viewer the settings, a supervisor everything. "" when
/// allowed, else why not.
std::string controlRefusal(const trust::ZapAuthenticator::Peer& peer, const proto::ControlRequest& request) {
  if (peer.role == trust::LinkRole::kSupervisor) return "";
  // What the operator's own view needs: the calibration in use (to follow a live change), the
  // settings, the media path's session key (the seat is checked by the caller), and a key frame
  // after its decoder lost one.
  if (peer.role == trust::LinkRole::kOperator &&
      (request.has_open_media_session() || request.has_get_calibration() || request.has_get_settings() ||
       request.has_request_key_frame()))
    return "";
  // A viewer may read the settings (they are in the health it receives anyway).
  if (peer.role == trust::LinkRole::kViewer && request.has_get_settings()) return "";
  const auto* field = proto::ControlRequest::descriptor()->FindFieldByNumber(int(request.request_case()));
  return trust::linkRoleWithArticle(peer.role) + " key (" + peer.name + ") may not send " +
         (field ? field->name() : std::string("this request")) + ": supervisor keys only";
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
  const bool secure;
  trust::LinkRefusals refusals;
  std::unique_ptr<trust::AllowedKeys> allowed;
  /// Bound before the sockets: libzmq asks it about every handshake (secure links only).
  std::unique_ptr<trust::ZapAuthenticator> authenticator;
  trust::OperatorSeat seat;
  std::map<std::string, trust::TokenBucket> control_buckets;  ///< per key name (service thread)
  std::mutex frames_mutex, state_mutex;
  zmq::socket_t frames, state, uplink, control;
  std::unique_ptr<trust::HandshakeMonitor> handshakes;
  LinkStats stats{"link server"};
  mutable std::mutex head_mutex;
  std::optional<proto::HeadTarget> head_target;
  /// The newest t_ns (its own clock) of each sender instance heard, the least recently heard
  /// first; a few senders at most (restarts of the operator PC, a second one).
  std::deque<std::pair<std::uint64_t, std::int64_t>> head_senders;
  static constexpr std::size_t kMaxHeadSenders = 16;
  std::mutex handler_mutex;
  ControlHandler handler;
  bool handler_ever_set = false;  ///< under handler_mutex: none yet means starting, none again stopping
  /// Control requests that came before the first handler (service thread only), oldest first.
  struct WaitingRequest {
    zmq::message_t identity;
    proto::ControlRequest request;
    std::int64_t since_ns = 0;
  };
  std::deque<WaitingRequest> waiting;
  static constexpr std::size_t kMaxWaiting = 64;
  const std::chrono::milliseconds control_wait_at_start;
  std::function<void(const std::string&)> seat_handler;  ///< under handler_mutex
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
  Impl(const LinkEndpoints& e, std::chrono::milliseconds wait_at_start)
      : secure(e.credentials.secure()),
        allowed(secure ? std::make_unique<trust::AllowedKeys>(e.credentials.allowed_dir) : nullptr),
        authenticator(secure ? std::make_unique<trust::ZapAuthenticator>(context.handle(), *allowed, refusals,
                                                                         roleMayConnect)
                             : nullptr),
        frames(bindSocket(context, zmq::socket_type::pub, e, LinkEndpoints::kFrames, "frames", 6)),
        state(bindSocket(context, zmq::socket_type::pub, e, LinkEndpoints::kState, "state",
                         LinkServer::kStateQueueMessages)),
        uplink(bindSocket(context, zmq::socket_type::pull, e, LinkEndpoints::kUplink, "uplink")),
        control(bindSocket(context, zmq::socket_type::router, e, LinkEndpoints::kControl, "control")),
        control_wait_at_start(wait_at_start) {
    uplink.set(zmq::sockopt::rcvhwm, 64);
    if (secure)
      handshakes = std::make_unique<trust::HandshakeMonitor>(
          context.handle(),
          std::vector<std::pair<void*, std::string>>{
              {frames.handle(), "frames"}, {state.handle(), "state"}, {uplink.handle(), "uplink"},
              {control.handle(), "control"}},
          refusals);
    service = std::thread([this] { serve(); });
  }

  /// The sender of a message on a secure link (ZAP's User-Id), while its key is still allowed:
  /// a key revoked from allowed/ is refused from the next message on, even on a connection that
  /// was let in before. Nothing on an insecure link.
  std::optional<trust::ZapAuthenticator::Peer> senderOf(zmq::message_t& message) {
    if (!secure) return std::nullopt;
    auto peer = trust::ZapAuthenticator::parseUserId(zmq_msg_gets(message.handle(), "User-Id"));
    if (peer && !allowed->find(peer->public_z85)) {
      refusals.count("revoked key", peer->name + "'s key is no longer in allowed/", peerAddressOf(message), peer->name,
                     linkNowNs());
      return std::nullopt;
    }
    return peer;
  }
  static std::string peerAddressOf(zmq::message_t& message) {
    const char* address = zmq_msg_gets(message.handle(), "Peer-Address");
    return address ? address : "";
  }

  /// May this uplink message pass? Head targets: the seated operator only; XR stats and
  /// telemetry: operators. Refusals counted (a refused operator learns why from the console).
  bool uplinkAllowed(zmq::message_t& message, const proto::Envelope& envelope) {
    if (!secure) return true;
    const auto peer = senderOf(message);
    const std::string address = peerAddressOf(message);
    if (!peer) return false;  // counted by senderOf
    if (peer->role != trust::LinkRole::kOperator) {
      refusals.count("role",
                     trust::linkRoleWithArticle(peer->role) + " key (" + peer->name +
                         ") may not send head targets or XR stats: operator keys only",
                     address, peer->name, linkNowNs());
      return false;
    }
    if (envelope.has_head_target()) {
      if (const auto holder = seat.claim(peer->name)) {
        refusals.count("operator seat",
                       "operator " + peer->name + " refused: the seat is held by " + *holder +
                           " (a supervisor can hand it over)",
                       address, peer->name, linkNowNs());
        return false;
      }
    }
    return true;
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
      if (!waiting.empty()) answerWaiting();
    }
  }

  /// Answers what waited for the first handler: by it once there is one, "still starting" to
  /// what waited too long.
  void answerWaiting() {
    const std::int64_t now = linkNowNs();
    std::lock_guard lock(handler_mutex);
    while (!waiting.empty()) {
      WaitingRequest& w = waiting.front();
      proto::ControlReply answer;
      if (handler) {
        answer = handler(w.request);
      } else if (now - w.since_ns >= std::chrono::nanoseconds(control_wait_at_start).count() || handler_ever_set) {
        answer = notServing();
      } else {
        return;  // the oldest may still wait, so may every later one
      }
      answer.set_id(w.request.id());
      proto::Envelope reply;
      *reply.mutable_control_reply() = std::move(answer);
      sendReply(w.identity, reply);
      waiting.pop_front();
    }
  }

  /// The answer when no handler serves control (handler_mutex held): not yet, or no longer.
  proto::ControlReply notServing() const {
    proto::ControlReply reply;
    reply.set_ok(false);
    reply.set_error(handler_ever_set ? "the robot is shutting down" : "the robot is still starting: ask again in a moment");
    return reply;
  }

  void sendReply(zmq::message_t& identity, proto::Envelope& reply) {
    reply.set_schema_version(kSchemaVersion);
    reply.set_sender_clock_ns(linkNowNs());
    control.send(identity, zmq::send_flags::sndmore | zmq::send_flags::dontwait);
    if (control.send(serialise(reply), zmq::send_flags::dontwait)) stats.countSent();
    if (reply.has_control_reply()) tell(LinkTap::Direction::kSent, reply);
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
      if (!uplinkAllowed(message, *envelope)) {
        stats.countDrop(DropReason::kRefused, "uplink");
        continue;
      }
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

  /// "" when this control request may run, else the reason (counted as a refusal): supervisors
  /// only on a secure link, at most kControlPerSecond per key.
  static constexpr double kControlPerSecond = 20, kControlBurst = 60;
  std::string controlAllowed(zmq::message_t& message, const proto::ControlRequest& request) {
    if (!secure) return "";
    const auto peer = senderOf(message);
    const std::string address = peerAddressOf(message);
    if (!peer) return "refused: your key is no longer allowed on this robot";
    if (std::string why = controlRefusal(*peer, request); !why.empty()) {
      refusals.count("role", why, address, peer->name, linkNowNs());
      return why;
    }
    if (peer->role == trust::LinkRole::kOperator && request.has_open_media_session()) {
      if (const auto holder = seat.claim(peer->name)) {
        const std::string why = "operator " + peer->name + " refused: the seat is held by " + *holder +
                                " (a supervisor can hand it over)";
        refusals.count("operator seat", why, address, peer->name, linkNowNs());
        return why;
      }
    }
    if (control_buckets.size() > 256) control_buckets.clear();
    auto bucket = control_buckets.try_emplace(peer->name, kControlPerSecond, kControlBurst).first;
    if (!bucket->second.take(linkNowNs())) {
      refusals.count("rate limit", "more than 20 control requests a second from " + peer->name, address, peer->name,
                     linkNowNs());
      return "refused: more than 20 control requests a second; slow down";
    }
    return "";
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
        const std::string refused = controlAllowed(parts[1], envelope->control_request());
        if (!refused.empty()) {
          reply.mutable_control_reply()->set_ok(false);
          reply.mutable_control_reply()->set_error(refused);
          reply.mutable_control_reply()->set_id(envelope->control_request().id());
        } else if (envelope->control_request().has_hand_over_operator_seat()) {
          tell(LinkTap::Direction::kReceived, *envelope);
          const std::string& name = envelope->control_request().hand_over_operator_seat().name();
          seat.handOver(name);
          spdlog::info("link: operator seat {}", name.empty() ? std::string("freed") : "handed to " + name);
          std::function<void(const std::string&)> on_seat;
          {
            std::lock_guard lock(handler_mutex);
            on_seat = seat_handler;
          }
          if (on_seat) on_seat(name);
          reply.mutable_control_reply()->set_ok(true);
          reply.mutable_control_reply()->set_id(envelope->control_request().id());
        } else {
          tell(LinkTap::Direction::kReceived, *envelope);
          std::lock_guard lock(handler_mutex);
          if (handler) {
            *reply.mutable_control_reply() = handler(envelope->control_request());
          } else if (!handler_ever_set && waiting.size() < kMaxWaiting) {
            waiting.push_back({std::move(parts[0]), std::move(*envelope->mutable_control_request()), linkNowNs()});
            continue;  // answered by answerWaiting
          } else {
            *reply.mutable_control_reply() = notServing();
          }
          reply.mutable_control_reply()->set_id(envelope->control_request().id());
        }
      } else {
        stats.countDrop(DropReason::kUnexpectedBody, "control");
        continue;
      }
      sendReply(parts[0], reply);
    }
  }
};

LinkServer::LinkServer(const LinkEndpoints& endpoints, std::chrono::milliseconds control_wait_at_start)
    : impl_(std::make_unique<Impl>(endpoints, control_wait_at_start)) {
  spdlog::info("link server on ports {}..{} ({})", endpoints.base_port, endpoints.base_port + 3,
               endpoints.credentials.secure() ? "CURVE: keys in " + endpoints.credentials.allowed_dir.string()
                                              : std::string("INSECURE: no keys"));
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
  impl_->handler_ever_set = impl_->handler_ever_set || handler != nullptr;
  impl_->handler = std::move(handler);
}

void LinkServer::setOperatorSeatHandler(std::function<void(const std::string& name)> handler) {
  std::lock_guard lock(impl_->handler_mutex);
  impl_->seat_handler = std::move(handler);
}

void LinkServer::setTap(std::shared_ptr<LinkTap> tap) {
  std::lock_guard lock(impl_->tap_mutex);
  impl_->tap = std::move(tap);
}

LinkStatsSnapshot LinkServer::stats() const { return impl_->stats.snapshot(); }

proto::LinkTrustHealth LinkServer::trustHealth() const {
  proto::LinkTrustHealth health;
  health.set_insecure(!impl_->secure);
  if (impl_->allowed) {
    const auto allowed = impl_->allowed->snapshot();
    for (const auto& key : allowed.keys)
      health.add_allowed(key.name + " (" + std::string(trust::linkRoleName(key.role)) + ")");
    for (const auto& error : allowed.errors) health.add_allowed_errors(error);
    health.set_allowed_reloads(allowed.reloads);
  }
  health.set_operator_seat(impl_->seat.holder());
  constexpr std::size_t kShown = 8;
  const auto refusals = impl_->refusals.snapshot();
  for (std::size_t i = 0; i < refusals.size() && i < kShown; ++i) {
    auto* r = health.add_refusals();
    r->set_cause(refusals[i].cause);
    r->set_detail(refusals[i].detail);
    r->set_peer(refusals[i].peer);
    r->set_name(refusals[i].name);
    r->set_count(refusals[i].count);
    r->set_last_t_ns(refusals[i].last_t_ns);
  }
  health.set_refused_total(impl_->refusals.total());
  return health;
}

}  // namespace telesphere::link
