// SPDX-License-Identifier: MIT
/// @brief SrtSender and SrtReceiver (see srt_frame_link.h) on libsrt's C API.
#include "app/bench/srt/srt_frame_link.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <srt/srt.h>
#include <syslog.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace telesphere::bench::srt {
namespace {

std::int64_t steadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// libsrt once per process (never cleaned up: sockets may outlive any one object); its own log
/// only for what is fatal.
void startLibrary() {
  static const bool started = [] {
    srt_startup();
    srt_setloglevel(LOG_CRIT);
    return true;
  }();
  (void)started;
}

std::string lastError(const std::string& what) { return what + ": " + srt_getlasterror_str(); }

sockaddr_in loopback(std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

/// The live-mode options both ends share; false with the reason.
bool configure(SRTSOCKET s, const SrtLinkOptions& o, std::string* error) {
  const SRT_TRANSTYPE live = SRTT_LIVE;
  const bool yes = true;
  const struct {
    SRT_SOCKOPT option;
    const void* value;
    int size;
    const char* name;
  } settings[] = {
      {SRTO_TRANSTYPE, &live, sizeof live, "SRTO_TRANSTYPE"},
      {SRTO_LATENCY, &o.latency_ms, sizeof o.latency_ms, "SRTO_LATENCY"},
      {SRTO_PAYLOADSIZE, &o.payload_bytes, sizeof o.payload_bytes, "SRTO_PAYLOADSIZE"},
      {SRTO_TLPKTDROP, &yes, sizeof yes, "SRTO_TLPKTDROP"},
      {SRTO_CONNTIMEO, &o.connect_timeout_ms, sizeof o.connect_timeout_ms, "SRTO_CONNTIMEO"},
  };
  for (const auto& s_ : settings) {
    if (srt_setsockflag(s, s_.option, s_.value, s_.size) == SRT_ERROR) {
      *error = lastError(std::string("srt: ") + s_.name);
      return false;
    }
  }
  return true;
}

SrtLinkStats statsOf(SRTSOCKET s, bool sender) {
  SrtLinkStats out;
  if (s == SRT_INVALID_SOCK) return out;
  SRT_TRACEBSTATS b{};
  if (srt_bstats(s, &b, 0) == SRT_ERROR) return out;
  out.packets_sent = b.pktSentUniqueTotal;
  out.packets_retransmitted = b.pktRetransTotal;
  out.packets_lost = sender ? b.pktSndLossTotal : b.pktRcvLossTotal;
  out.packets_dropped_late = sender ? b.pktSndDropTotal : b.pktRcvDropTotal;
  out.bytes_sent = b.byteSentTotal;
  out.rtt_ms = b.msRTT;
  return out;
}

}  // namespace

std::unique_ptr<SrtSender> SrtSender::listen(const SrtLinkOptions& options, std::uint16_t port, std::string* error) {
  startLibrary();
  error->clear();
  const SRTSOCKET s = srt_create_socket();
  if (s == SRT_INVALID_SOCK) {
    *error = lastError("srt: socket");
    return nullptr;
  }
  sockaddr_in a = loopback(port);
  int length = sizeof a;
  const bool no = false;
  if (!configure(s, options, error) || srt_setsockflag(s, SRTO_RCVSYN, &no, sizeof no) == SRT_ERROR ||
      srt_bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == SRT_ERROR ||
      srt_getsockname(s, reinterpret_cast<sockaddr*>(&a), &length) == SRT_ERROR || srt_listen(s, 1) == SRT_ERROR) {
    if (error->empty()) *error = lastError("srt: listen on 127.0.0.1:" + std::to_string(port));
    srt_close(s);
    return nullptr;
  }
  return std::unique_ptr<SrtSender>(new SrtSender(s, ntohs(a.sin_port)));
}

SrtSender::~SrtSender() {
  if (socket_ >= 0) srt_close(socket_);
  if (listener_ >= 0) srt_close(listener_);
}

bool SrtSender::accept(int timeout_ms, std::string* error) {
  // The listener does not block (set in listen()): asked every 5 ms until the deadline.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (true) {
    sockaddr_in peer{};
    int length = sizeof peer;
    const SRTSOCKET s = srt_accept(listener_, reinterpret_cast<sockaddr*>(&peer), &length);
    if (s != SRT_INVALID_SOCK) {
      socket_ = s;
      return true;
    }
    if (srt_getlasterror(nullptr) != SRT_EASYNCRCV) {
      *error = lastError("srt: accept");
      return false;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      *error = "srt: no caller within " + std::to_string(timeout_ms) + " ms";
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

bool SrtSender::send(std::span<const std::uint8_t> datagram, std::string* error) {
  if (socket_ < 0) {
    *error = "srt: no caller";
    return false;
  }
  if (srt_sendmsg2(socket_, reinterpret_cast<const char*>(datagram.data()), int(datagram.size()), nullptr) == SRT_ERROR) {
    *error = lastError("srt: send");
    return false;
  }
  return true;
}

SrtLinkStats SrtSender::stats() const { return statsOf(socket_, true); }

struct SrtReceiver::Impl {
  SRTSOCKET socket = SRT_INVALID_SOCK;
  DatagramHandler on_datagram;
  IdleHandler on_idle;
  std::atomic<bool> stop{false};
  std::thread thread;

  void run() {
    std::vector<char> buffer(1500);
    std::int64_t last_idle_ns = steadyNs();
    while (!stop) {
      SRT_MSGCTRL control = srt_msgctrl_default;
      const int n = srt_recvmsg2(socket, buffer.data(), int(buffer.size()), &control);
      const std::int64_t now_ns = steadyNs();
      if (n > 0) {
        on_datagram(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(buffer.data()), std::size_t(n)),
                    now_ns);
      } else if (n == SRT_ERROR && srt_getlasterror(nullptr) != SRT_EASYNCRCV) {
        if (srt_getsockstate(socket) != SRTS_CONNECTED) break;  // the sender went away
      }
      if (now_ns - last_idle_ns >= 5'000'000) {
        on_idle(now_ns);
        last_idle_ns = now_ns;
      }
    }
  }
};

std::unique_ptr<SrtReceiver> SrtReceiver::connect(const SrtLinkOptions& options, std::uint16_t port,
                                                  DatagramHandler on_datagram, IdleHandler on_idle, std::string* error) {
  startLibrary();
  error->clear();
  auto impl = std::make_unique<Impl>();
  impl->socket = srt_create_socket();
  if (impl->socket == SRT_INVALID_SOCK) {
    *error = lastError("srt: socket");
    return nullptr;
  }
  const int receive_timeout_ms = 10;
  sockaddr_in a = loopback(port);
  if (!configure(impl->socket, options, error) ||
      srt_setsockflag(impl->socket, SRTO_RCVTIMEO, &receive_timeout_ms, sizeof receive_timeout_ms) == SRT_ERROR ||
      srt_connect(impl->socket, reinterpret_cast<sockaddr*>(&a), sizeof a) == SRT_ERROR) {
    if (error->empty()) *error = lastError("srt: connect to 127.0.0.1:" + std::to_string(port));
    srt_close(impl->socket);
    return nullptr;
  }
  impl->on_datagram = std::move(on_datagram);
  impl->on_idle = std::move(on_idle);
  Impl* raw = impl.get();
  impl->thread = std::thread([raw] { raw->run(); });
  return std::unique_ptr<SrtReceiver>(new SrtReceiver(std::move(impl)));
}

SrtReceiver::SrtReceiver(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

SrtReceiver::~SrtReceiver() {
  impl_->stop = true;
  if (impl_->thread.joinable()) impl_->thread.join();
  srt_close(impl_->socket);
}

SrtLinkStats SrtReceiver::stats() const { return statsOf(impl_->socket, false); }

}  // namespace telesphere::bench::srt
