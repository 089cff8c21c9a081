// SPDX-License-Identifier: MIT
#include "robot/arm/xarm/controller_simulator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <list>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "robot/clock/clock.h"
#include "robot/arm/xarm/tcp_socket.h"
#include "robot/arm/xarm/xarm_protocol.h"
#include "robot/arm/xarm/xarm_report.h"

namespace telesphere::xarm {

using namespace std::chrono_literals;
using robot::arm::JointVector;

namespace {

constexpr int kEmergencyStop = 1, kJointLimit = 23, kCollision = 31;
constexpr int kWarningParameter = 12, kWarningNoSuchCommand = 13;

}  // namespace

/// A position-mode joint move: the set-point walks from `from` to `to` at `speed` (the joint
/// with the longest way at that speed, the others in proportion).
struct JointMove {
  JointVector from, to;
  double duration_s = 0;
  std::int64_t start_ns = 0;
};

struct ControllerSimulator::Impl {
  ControllerSimulatorOptions options;
  robot::clock::SteadyClock clock;
  TcpListener command_listener, report_listener, normal_listener;

  mutable std::mutex mutex;  ///< everything below
  robot::arm::SimulatedArm arm;
  std::uint8_t state = std::uint8_t(ControllerState::kStopped);
  std::uint8_t mode = std::uint8_t(ControllerMode::kPosition);
  bool enabled = false;
  int error = 0, warning = 0;
  bool emergency_held = false;
  std::optional<JointMove> move;
  JointVector q_reported = JointVector::Zero();
  bool reports_paused = false, replies_paused = false;
  std::uint64_t servo_commands = 0, reports_sent = 0, heartbeats = 0;
  std::uint16_t last_protocol = 0;
  double payload_kg = 0;
  std::array<double, 3> payload_com_mm{};
  int collision_sensitivity = 3;
  bool payload_writes_ignored = false;
  std::int64_t next_normal_ns = 0;

  struct Client {
    TcpSocket socket;
    std::thread thread;  ///< command clients only
    std::atomic<bool> done{false};
  };
  std::list<std::unique_ptr<Client>> command_clients, report_clients, normal_clients;
  std::mutex report_send_mutex;  ///< report clients' sockets (physics thread and sendRawReport)

  std::atomic<bool> stopping{false};
  std::thread accept_thread, physics_thread;

  explicit Impl(const ControllerSimulatorOptions& o)
      : options(o), arm(clock, o.arm), payload_kg(o.payload_kg), collision_sensitivity(o.collision_sensitivity) {
    q_reported = arm.trueJoints();
  }

  ~Impl() {
    stopping = true;
    if (accept_thread.joinable()) accept_thread.join();
    if (physics_thread.joinable()) physics_thread.join();
    std::list<std::unique_ptr<Client>> clients;
    {
      std::lock_guard lock(mutex);
      clients.swap(command_clients);
    }
    for (auto& c : clients) {
      c->socket.shutdown();
      if (c->thread.joinable()) c->thread.join();
    }
  }

  std::uint8_t statusLocked() const {
    std::uint8_t s = 0;
    if (error != 0) s |= kStatusError;
    if (warning != 0) s |= kStatusWarning;
    if (!enabled || (state != std::uint8_t(ControllerState::kMoving) && state != std::uint8_t(ControllerState::kReady)))
      s |= kStatusNotReady;
    return s;
  }

  void stopLocked(int code) {
    if (code != 0) error = code;
    state = std::uint8_t(ControllerState::kStopped);
    move.reset();
    arm.triggerStop();
  }

  // ---- the command port -------------------------------------------------------------------------

  /// The reply to one request (nothing: no reply, e.g. while replies are paused).
  std::vector<std::uint8_t> answer(const Frame& f) {
    std::lock_guard lock(mutex);
    if (f.protocol == kHeartbeatProtocol) {  // the old heartbeat frame: no reply
      ++heartbeats;
      return {};
    }
    last_protocol = f.protocol;
    std::vector<std::uint8_t> params;
    const auto in = std::span<const std::uint8_t>(f.body);
    std::uint8_t extra = 0;  // status bits beyond the controller's own
    switch (static_cast<Register>(f.reg)) {
      case Register::kGetVersion: {
        params.assign(40, 0);
        std::copy_n(options.firmware.begin(), std::min<std::size_t>(39, options.firmware.size()), params.begin());
        break;
      }
      case Register::kGetRobotSn: {
        params.assign(40, 0);
        const std::string sn = options.robot_sn + std::string(1, '\0') + options.box_sn;
        std::copy_n(sn.begin(), std::min<std::size_t>(39, sn.size()), params.begin());
        break;
      }
      case Register::kSetTcpLoad:
        if (in.size() < 16) {
          warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        if (!payload_writes_ignored) {
          payload_kg = readF32(in, 0);
          for (std::size_t i = 0; i < 3; ++i) payload_com_mm[i] = readF32(in, 4 + 4 * i);
        }
        break;
      case Register::kSetCollisionSensitivity:
        if (in.empty() || in[0] > 5) {
          warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        collision_sensitivity = in[0];
        // A "system reset": motion stops, the command cache is cleared; set state 0 to move again.
        move.reset();
        state = std::uint8_t(ControllerState::kStopped);
        break;
      case Register::kMotionEnable:
        if (in.size() < 2) {
          warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        enabled = in[1] != 0;
        move.reset();
        state = std::uint8_t(enabled ? ControllerState::kModeChanged : ControllerState::kStopped);
        break;
      case Register::kSetState:
        if (in.empty()) {
          warning = kWarningParameter;
          extra = kStatusFailed;
        } else if (in[0] == std::uint8_t(ControllerState::kStart)) {
          if (error != 0 || !enabled) {
            extra = kStatusFailed;
          } else {
            state = std::uint8_t(ControllerState::kReady);
            arm.clearStop();
          }
        } else if (in[0] == std::uint8_t(ControllerState::kStopped)) {
          stopLocked(0);
        } else if (in[0] == std::uint8_t(ControllerState::kPaused)) {
          state = std::uint8_t(ControllerState::kPaused);
          move.reset();
        }
        break;
      case Register::kGetState: params.push_back(state); break;
      case Register::kGetCmdNum: appendU16(params, move ? 1 : 0); break;
      case Register::kGetErrorWarning:
        params.push_back(std::uint8_t(error));
        params.push_back(std::uint8_t(warning));
        break;
      case Register::kCleanError:
        if (!emergency_held) error = 0;
        enabled = false;  // a "system reset": motors need enabling again
        state = std::uint8_t(ControllerState::kStopped);
        break;
      case Register::kCleanWarning: warning = 0; break;
      case Register::kSetMode:
        if (in.empty()) {
          warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        mode = in[0];
        move.reset();
        state = std::uint8_t(ControllerState::kModeChanged);
        break;
      case Register::kMoveJoint: {
        const auto q = jointsOfMoveParams(in);
        const bool ready = enabled && error == 0 && mode == std::uint8_t(ControllerMode::kPosition) &&
                           (state == std::uint8_t(ControllerState::kReady) || state == std::uint8_t(ControllerState::kMoving));
        if (!q || !ready) {
          if (!q) warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        JointVector to;
        for (int i = 0; i < 6; ++i) to[i] = (*q)[std::size_t(i)];
        if (!arm.kinematics().withinLimits(to)) {
          warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        const double speed = std::clamp(double(readF32(in, 28)), 1e-3, options.arm.max_velocity);
        JointMove m{arm.setPoint(), to, 0, clock.nowNs()};
        m.duration_s = (to - m.from).cwiseAbs().maxCoeff() / speed;
        move = m;
        state = std::uint8_t(ControllerState::kMoving);
        params = {0, 0};
        break;
      }
      case Register::kMoveServoJoint: {
        const auto q = jointsOfMoveParams(in);
        const bool ready = enabled && error == 0 && mode == std::uint8_t(ControllerMode::kServo) &&
                           (state == std::uint8_t(ControllerState::kReady) || state == std::uint8_t(ControllerState::kMoving));
        if (!q) {
          warning = kWarningParameter;
          extra = kStatusFailed;
          break;
        }
        if (!ready) break;  // ignored; the status bits say why
        JointVector target;
        for (int i = 0; i < 6; ++i) target[i] = (*q)[std::size_t(i)];
        if (!arm.kinematics().withinLimits(target, 1e-3)) {
          stopLocked(kJointLimit);
          break;
        }
        arm.sendTarget(target);
        ++servo_commands;
        break;
      }
      case Register::kGetJointPositions:
        for (int i = 0; i < 7; ++i) appendF32(params, i < 6 ? float(q_reported[i]) : 0.0f);
        break;
      default:
        warning = kWarningNoSuchCommand;
        extra = kStatusFailed;
        break;
    }
    if (replies_paused) return {};
    return encodeResponse(f.transaction, f.reg, std::uint8_t(statusLocked() | extra), params, f.protocol);
  }

  void serveCommands(Client& c) {
    FrameReader reader;
    std::vector<std::uint8_t> buffer(2048);
    bool speaks_id3 = false;
    auto last_heard = std::chrono::steady_clock::now();
    while (!stopping && !c.done) {
      std::size_t n = 0;
      std::string error_text;
      const auto got = c.socket.receive(buffer, 20ms, &n, &error_text);
      if (got == TcpSocket::Received::kTimeout) {
        // An identifier-3 client that fell silent is dropped (the heartbeat it promised is missing).
        if (speaks_id3 && std::chrono::steady_clock::now() - last_heard > options.id3_silence_limit) break;
        continue;
      }
      if (got != TcpSocket::Received::kData) break;
      last_heard = std::chrono::steady_clock::now();
      reader.feed(std::span<const std::uint8_t>(buffer.data(), n));
      while (auto frame = reader.next()) {
        speaks_id3 = speaks_id3 || frame->protocol == kPrivateProtocolWithHeartbeat;
        const auto reply = answer(*frame);
        if (reply.empty()) continue;
        if (options.reply_delay.count() > 0) std::this_thread::sleep_for(options.reply_delay);
        if (!c.socket.sendAll(reply, 100ms, &error_text)) break;
      }
      if (reader.failed()) break;  // the controller drops a client that sends garbage
    }
    c.socket.shutdown();
    c.done = true;
  }

  // ---- reports and physics ----------------------------------------------------------------------

  void physics() {
    auto next = std::chrono::steady_clock::now();
    while (!stopping) {
      next += 1ms;
      std::this_thread::sleep_until(next);
      std::vector<std::vector<std::uint8_t>> reports;  // one per state the arm published (none skipped)
      {
        std::lock_guard lock(mutex);
        if (move) {
          const double t = double(clock.nowNs() - move->start_ns) * 1e-9;
          const double s = move->duration_s > 0 ? std::clamp(t / move->duration_s, 0.0, 1.0) : 1.0;
          arm.sendTarget(move->from + s * (move->to - move->from));
          if (s >= 1.0 && (arm.trueJoints() - move->to).cwiseAbs().maxCoeff() < 1e-3 &&
              arm.trueVelocities().cwiseAbs().maxCoeff() < 1e-3) {
            move.reset();
            state = std::uint8_t(ControllerState::kReady);
          }
        }
        arm.update();
        if (mode == std::uint8_t(ControllerMode::kServo) && (state == std::uint8_t(ControllerState::kReady) ||
                                                              state == std::uint8_t(ControllerState::kMoving)))
          state = std::uint8_t(arm.trueVelocities().cwiseAbs().maxCoeff() > 1e-3 ? ControllerState::kMoving
                                                                                   : ControllerState::kReady);
        while (auto s = arm.pollState()) {  // several after a late wake-up: each is a report
          q_reported = s->q;
          if (reports_paused) continue;
          RealtimeReport r;
          r.state = state;
          r.mode = mode;
          r.commands = move ? 1 : 0;
          for (int i = 0; i < 6; ++i) r.q[std::size_t(i)] = q_reported[i];
          reports.push_back(encodeRealtimeReport(r));
          ++reports_sent;
        }
      }
      for (const auto& report : reports) sendToReportClients(report);
      sendNormalReport();
      reapClients();
    }
  }

  /// Port 30001 at 5 Hz: the state, the codes, the payload and the sensitivities.
  void sendNormalReport() {
    std::vector<std::uint8_t> bytes;
    {
      std::lock_guard lock(mutex);
      const std::int64_t now = clock.nowNs();
      if (now < next_normal_ns) return;
      next_normal_ns = now + 200'000'000;
      NormalReport r;
      r.realtime.state = state;
      r.realtime.mode = mode;
      for (int i = 0; i < 6; ++i) r.realtime.q[std::size_t(i)] = q_reported[i];
      r.enabled = enabled ? 0xff : 0;
      r.error = std::uint8_t(error);
      r.warning = std::uint8_t(warning);
      r.payload_kg = payload_kg;
      r.payload_com_mm = payload_com_mm;
      r.collision_sensitivity = std::uint8_t(collision_sensitivity);
      r.teach_sensitivity = 3;
      r.gravity = {0.0, 0.0, -1.0};
      bytes = encodeNormalReport(r);
    }
    std::lock_guard send_lock(report_send_mutex);
    for (auto& c : normal_clients) {
      std::string error_text;
      if (!c->done && !c->socket.sendAll(bytes, 20ms, &error_text)) {
        c->socket.shutdown();
        c->done = true;
      }
    }
  }

  void sendToReportClients(std::span<const std::uint8_t> bytes) {
    std::lock_guard send_lock(report_send_mutex);
    for (auto& c : report_clients) {
      std::string error_text;
      if (!c->done && !c->socket.sendAll(bytes, 20ms, &error_text)) {
        c->socket.shutdown();
        c->done = true;
      }
    }
  }

  void reapClients() {
    std::list<std::unique_ptr<Client>> finished;
    {
      std::lock_guard lock(mutex);
      for (auto it = command_clients.begin(); it != command_clients.end();)
        if ((*it)->done) finished.splice(finished.end(), command_clients, it++);
        else ++it;
    }
    for (auto& c : finished)
      if (c->thread.joinable()) c->thread.join();
    std::lock_guard send_lock(report_send_mutex);
    report_clients.remove_if([](const auto& c) { return c->done.load(); });
    normal_clients.remove_if([](const auto& c) { return c->done.load(); });
  }

  void acceptClients() {
    while (!stopping) {
      std::string error_text;
      if (auto s = command_listener.accept(10ms, &error_text)) {
        auto client = std::make_unique<Client>();
        client->socket = std::move(*s);
        Client* raw = client.get();
        std::lock_guard lock(mutex);
        command_clients.push_back(std::move(client));
        raw->thread = std::thread([this, raw] { serveCommands(*raw); });
      }
      if (auto s = report_listener.accept(10ms, &error_text)) {
        auto client = std::make_unique<Client>();
        client->socket = std::move(*s);
        std::lock_guard send_lock(report_send_mutex);
        report_clients.push_back(std::move(client));
      }
      if (auto s = normal_listener.accept(5ms, &error_text)) {
        auto client = std::make_unique<Client>();
        client->socket = std::move(*s);
        std::lock_guard send_lock(report_send_mutex);
        normal_clients.push_back(std::move(client));
      }
    }
  }
};

ControllerSimulator::ControllerSimulator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ControllerSimulator::~ControllerSimulator() = default;

std::unique_ptr<ControllerSimulator> ControllerSimulator::start(const ControllerSimulatorOptions& options,
                                                                std::string* error) {
  auto impl = std::make_unique<Impl>(options);
  auto command = TcpListener::listen(options.address, options.command_port, error);
  if (!command) return nullptr;
  auto report = TcpListener::listen(options.address, options.report_port, error);
  if (!report) return nullptr;
  auto normal = TcpListener::listen(options.address, options.normal_report_port, error);
  if (!normal) return nullptr;
  impl->command_listener = std::move(*command);
  impl->report_listener = std::move(*report);
  impl->normal_listener = std::move(*normal);
  Impl* raw = impl.get();
  impl->physics_thread = std::thread([raw] { raw->physics(); });
  impl->accept_thread = std::thread([raw] { raw->acceptClients(); });
  return std::unique_ptr<ControllerSimulator>(new ControllerSimulator(std::move(impl)));
}

int ControllerSimulator::commandPort() const { return impl_->command_listener.port(); }
int ControllerSimulator::reportPort() const { return impl_->report_listener.port(); }
int ControllerSimulator::normalReportPort() const { return impl_->normal_listener.port(); }

void ControllerSimulator::setPayloadWritesIgnored(bool ignored) {
  std::lock_guard lock(impl_->mutex);
  impl_->payload_writes_ignored = ignored;
}

void ControllerSimulator::pressEmergencyStop() {
  std::lock_guard lock(impl_->mutex);
  impl_->emergency_held = true;
  impl_->stopLocked(kEmergencyStop);
  impl_->enabled = false;
}

void ControllerSimulator::releaseEmergencyStop() {
  std::lock_guard lock(impl_->mutex);
  impl_->emergency_held = false;
}

void ControllerSimulator::collide() {
  std::lock_guard lock(impl_->mutex);
  impl_->stopLocked(kCollision);
}

void ControllerSimulator::setReportsPaused(bool paused) {
  std::lock_guard lock(impl_->mutex);
  impl_->reports_paused = paused;
}

void ControllerSimulator::setRepliesPaused(bool paused) {
  std::lock_guard lock(impl_->mutex);
  impl_->replies_paused = paused;
}

void ControllerSimulator::dropConnections() {
  {
    std::lock_guard lock(impl_->mutex);
    for (auto& c : impl_->command_clients) {
      c->done = true;
      c->socket.shutdown();
    }
  }
  std::lock_guard send_lock(impl_->report_send_mutex);
  for (auto* clients : {&impl_->report_clients, &impl_->normal_clients})
    for (auto& c : *clients) {
      c->done = true;
      c->socket.shutdown();
    }
}

void ControllerSimulator::sendRawReport(std::span<const std::uint8_t> bytes) { impl_->sendToReportClients(bytes); }

void ControllerSimulator::sendRawReply(std::span<const std::uint8_t> bytes) {
  std::lock_guard lock(impl_->mutex);
  for (auto& c : impl_->command_clients) {
    std::string error_text;
    if (!c->done) c->socket.sendAll(bytes, 20ms, &error_text);
  }
}

ControllerSimulator::Snapshot ControllerSimulator::snapshot() const {
  std::lock_guard lock(impl_->mutex);
  Snapshot s;
  s.state = impl_->state;
  s.mode = impl_->mode;
  s.error = impl_->error;
  s.warning = impl_->warning;
  s.enabled = impl_->enabled;
  s.q_true = impl_->arm.trueJoints();
  s.set_point = impl_->arm.setPoint();
  s.servo_commands = impl_->servo_commands;
  s.reports_sent = impl_->reports_sent;
  s.last_protocol = impl_->last_protocol;
  s.heartbeats = impl_->heartbeats;
  s.payload_kg = impl_->payload_kg;
  s.payload_com_mm = impl_->payload_com_mm;
  s.collision_sensitivity = impl_->collision_sensitivity;
  s.command_clients = int(std::count_if(impl_->command_clients.begin(), impl_->command_clients.end(),
                                        [](const auto& c) { return !c->done; }));
  {
    std::lock_guard send_lock(impl_->report_send_mutex);
    s.report_clients = int(std::count_if(impl_->report_clients.begin(), impl_->report_clients.end(),
                                         [](const auto& c) { return !c->done; }));
    s.normal_report_clients = int(std::count_if(impl_->normal_clients.begin(), impl_->normal_clients.end(),
                                                [](const auto& c) { return !c->done; }));
  }
  return s;
}

}  // namespace telesphere::xarm
