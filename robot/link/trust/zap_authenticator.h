// SPDX-License-Identifier: MIT
/// @brief Decides who may finish a CURVE handshake with the robot's sockets (DESIGN.md §10): the
///        ZeroMQ Authentication Protocol (ZAP, RFC 27) handler of the robot's ZeroMQ context.
///        libzmq does the cryptography and asks this handler, once per connection, whether the
///        client's public key may in on a socket's domain. Allowed: a key in allowed/ whose role
///        the domain admits; the connection's messages then carry User-Id "role:name", which the
///        link checks per message. Refused, counted by cause and address: an unknown key, a role
///        the domain does not admit, more handshakes per address than the rate limit. allowed/ is
///        read again every second when it changed, whether or not anyone connects.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "robot/link/trust/allowed_keys.h"
#include "robot/link/trust/link_refusals.h"

namespace telesphere::link::trust {

class ZapAuthenticator {
 public:
  /// Which roles a ZAP domain (set per socket with ZMQ_ZAP_DOMAIN) admits.
  using DomainPolicy = std::function<bool(const std::string& domain, LinkRole role)>;
  /// Handshakes per address: kHandshakesPerSecond on average, kHandshakeBurst at once.
  static constexpr double kHandshakesPerSecond = 10;
  static constexpr double kHandshakeBurst = 40;

  /// Binds inproc://zeromq.zap.01 in `zmq_context` (call before the context's sockets bind) and
  /// answers on its own thread; allowed/ is re-read at most once a second.
  ZapAuthenticator(void* zmq_context, AllowedKeys& allowed, LinkRefusals& refusals, DomainPolicy policy);
  ~ZapAuthenticator();
  ZapAuthenticator(const ZapAuthenticator&) = delete;
  ZapAuthenticator& operator=(const ZapAuthenticator&) = delete;

  /// The User-Id of an allowed peer: "role:name:public key"; and back.
  static std::string userId(const LinkKey& key);
  struct Peer {
    LinkRole role;
    std::string name;
    std::string public_z85;  ///< to tell, per message, whether the key is still allowed
  };
  static std::optional<Peer> parseUserId(const char* user_id);

 private:
  void serve();

  void* socket_;
  AllowedKeys& allowed_;
  LinkRefusals& refusals_;
  DomainPolicy policy_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace telesphere::link::trust
