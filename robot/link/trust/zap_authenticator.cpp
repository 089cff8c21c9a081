// SPDX-License-Identifier: MIT
/// @brief The robot's ZAP handler (see zap_authenticator.h). The request and reply frames are
///        RFC 27's; the cryptography is libzmq's (with libsodium), none of it here.
#include "robot/link/trust/zap_authenticator.h"

#include <zmq.h>

#include <chrono>
#include <map>
#include <stdexcept>
#include <vector>

#include "robot/link/trust/token_bucket.h"

namespace telesphere::link::trust {
namespace {

std::int64_t steadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// Receives the rest of a multipart message; false when the socket is closing.
bool receiveParts(void* socket, std::vector<std::string>& parts) {
  parts.clear();
  int more = 1;
  while (more) {
    zmq_msg_t message;
    zmq_msg_init(&message);
    if (zmq_msg_recv(&message, socket, 0) < 0) {
      zmq_msg_close(&message);
      return false;
    }
    parts.emplace_back(static_cast<const char*>(zmq_msg_data(&message)), zmq_msg_size(&message));
    more = zmq_msg_more(&message);
    zmq_msg_close(&message);
  }
  return true;
}

void sendReply(void* socket, const std::string& request_id, const char* status, const std::string& text,
               const std::string& user_id) {
  const std::string frames[] = {"1.0", request_id, status, text, user_id, ""};
  for (std::size_t i = 0; i < 6; ++i) zmq_send(socket, frames[i].data(), frames[i].size(), i < 5 ? ZMQ_SNDMORE : 0);
}

}  // namespace

ZapAuthenticator::ZapAuthenticator(void* zmq_context, AllowedKeys& allowed, LinkRefusals& refusals, DomainPolicy policy)
    : socket_(zmq_socket(zmq_context, ZMQ_REP)), allowed_(allowed), refusals_(refusals), policy_(std::move(policy)) {
  const int linger = 0;
  zmq_setsockopt(socket_, ZMQ_LINGER, &linger, sizeof linger);
  if (!socket_ || zmq_bind(socket_, "inproc://zeromq.zap.01") != 0) {
    if (socket_) zmq_close(socket_);
    throw std::runtime_error(std::string("link: cannot start the key check (ZAP): ") + zmq_strerror(zmq_errno()));
  }
  thread_ = std::thread([this] { serve(); });
}

ZapAuthenticator::~ZapAuthenticator() {
  running_ = false;
  thread_.join();
  zmq_close(socket_);
}

std::string ZapAuthenticator::userId(const LinkKey& key) {
  return std::string(linkRoleName(key.role)) + ":" + key.name + ":" + key.public_z85;
}

std::optional<ZapAuthenticator::Peer> ZapAuthenticator::parseUserId(const char* user_id) {
  if (!user_id) return std::nullopt;
  const std::string text(user_id);
  // Names have no ':' (checkKeyName); Z85 keys may, so the key is everything after the second.
  const auto first = text.find(':');
  if (first == std::string::npos) return std::nullopt;
  const auto second = text.find(':', first + 1);
  if (second == std::string::npos) return std::nullopt;
  const auto role = parseLinkRole(std::string_view(text).substr(0, first));
  if (!role) return std::nullopt;
  return Peer{*role, text.substr(first + 1, second - first - 1), text.substr(second + 1)};
}

void ZapAuthenticator::serve() {
  std::map<std::string, TokenBucket> buckets;  // per address
  std::int64_t last_refresh_ns = 0;
  std::vector<std::string> request;
  while (running_) {
    zmq_pollitem_t item{socket_, 0, ZMQ_POLLIN, 0};
    const int ready = zmq_poll(&item, 1, 100);
    if (steadyNs() - last_refresh_ns > 1'000'000'000) {
      allowed_.refresh();
      last_refresh_ns = steadyNs();
    }
    if (ready <= 0 || !(item.revents & ZMQ_POLLIN)) continue;
    if (!receiveParts(socket_, request)) continue;
    // RFC 27: version, request id, domain, address, routing id, mechanism, credentials...
    if (request.size() < 6) {
      sendReply(socket_, request.size() > 1 ? request[1] : "", "500", "malformed ZAP request", "");
      continue;
    }
    const std::string& request_id = request[1];
    const std::string& domain = request[2];
    const std::string& address = request[3];
    const std::string& mechanism = request[5];
    const std::int64_t now = steadyNs();
    if (buckets.size() > 4096) buckets.clear();  // a flood from many addresses: start over
    auto bucket = buckets.try_emplace(address, kHandshakesPerSecond, kHandshakeBurst).first;
    if (!bucket->second.take(now)) {
      refusals_.count("rate limit", "more than " + std::to_string(int(kHandshakesPerSecond)) + " handshakes a second",
                      address, "", now);
      sendReply(socket_, request_id, "300", "too many handshakes: wait and try again", "");
      continue;
    }
    if (mechanism != "CURVE" || request.size() < 7 || request[6].size() != 32) {
      refusals_.count("no key", "the peer used " + mechanism + ", not CURVE", address, "", now);
      sendReply(socket_, request_id, "400", "a key is required (CURVE)", "");
      continue;
    }
    char z85[41] = {};
    zmq_z85_encode(z85, reinterpret_cast<const std::uint8_t*>(request[6].data()), 32);
    const auto key = allowed_.find(z85);
    if (!key) {
      refusals_.count("unknown key", std::string("public key ") + std::string(z85, 8) + "… is not in allowed/",
                      address, "", now);
      sendReply(socket_, request_id, "400", "unknown key: ask the supervisor to add your .pub to the robot's allowed/",
                "");
      continue;
    }
    if (!policy_(domain, key->role)) {
      refusals_.count("role",
                      std::string(linkRoleName(key->role)) + " " + key->name + " may not connect to " + domain, address,
                      key->name, now);
      sendReply(socket_, request_id, "400",
                linkRoleWithArticle(key->role) + " key may not use the " + domain + " channel", "");
      continue;
    }
    sendReply(socket_, request_id, "200", "OK", userId(*key));
  }
}

}  // namespace telesphere::link::trust
