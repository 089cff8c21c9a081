// SPDX-License-Identifier: MIT
/// @brief runReplay (see robot_replay.h).
#include "app/robot_replay.h"

#include <cstdio>
#include <iostream>
#include <thread>

#include "robot/link/link_server.h"
#include "robot/record/link_recorder.h"
#include "robot/record/recording_player.h"

namespace telesphere::app {

int runReplay(const RobotOptions& o, std::atomic<bool>& stop) {
  std::string error;
  auto replayer = record::RecordingPlayer::open(o.replay_path, &error);
  if (!replayer) {
    std::cerr << "telesphere-robot: --replay: " << error << '\n';
    return 1;
  }
  const record::McapSummary& s = replayer->summary();
  // Declared before the server: its thread may call the handler until the server is gone.
  const std::string refusal = "this is a replay of " + o.replay_path + ": the robot cannot be controlled";
  link::LinkEndpoints endpoints;
  endpoints.base_port = o.port;
  endpoints.credentials = o.credentials;
  std::unique_ptr<link::LinkServer> server;
  try {
    server = std::make_unique<link::LinkServer>(endpoints);
  } catch (const std::exception& e) {
    std::cerr << "telesphere-robot: cannot open the link on ports " << o.port << ".." << o.port + 3 << ": " << e.what()
              << '\n';
    return 2;
  }
  // The calibration in use where the replay is: an XR app asks for it as of a live robot. The
  // rest is refused.
  server->setControlHandler([&refusal, &replayer](const link::proto::ControlRequest& request) {
    link::proto::ControlReply reply;
    reply.set_id(request.id());
    if (request.get_calibration()) {
      if (const auto calibration = replayer->calibrationNow()) {
        reply.set_ok(true);
        *reply.mutable_calibration() = *calibration;
        return reply;
      }
      reply.set_error(refusal + " (and it holds no calibration: recorded before calibrations were attached)");
      return reply;
    }
    reply.set_ok(false);
    reply.set_error(refusal);
    return reply;
  });
  std::shared_ptr<record::LinkRecorder> recorder;
  if (!o.record_path.empty()) {
    record::LinkRecorderOptions recording;
    recording.mcap.compression = *record::parseCompression(o.record_compression);
    if (!(recorder = record::LinkRecorder::start(o.record_path, recording, &error))) {
      std::cerr << "telesphere-robot: --record: " << error << '\n';
      server->setControlHandler(nullptr);
      return 1;
    }
    server->setTap(recorder);
  }
  std::fprintf(stderr, "telesphere-robot: replaying %s (%llu messages, %.1f s) at %gx%s on port %d\n",
               o.replay_path.c_str(), static_cast<unsigned long long>(s.messages),
               double(s.end_ns - s.start_ns) * 1e-9, o.replay_rate, o.replay_loop ? ", looping" : "", o.port);
  record::RecordingPlayerOptions options;
  options.rate = o.replay_rate;
  options.loop = o.replay_loop;
  // The duration option stops a replay as it stops a robot.
  std::thread timer;
  if (o.duration_s > 0)
    timer = std::thread([&stop, &o] {
      const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.duration_s);
      while (!stop && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      stop = true;
    });
  const bool whole = replayer->run(*server, options, stop, &error);
  stop = true;
  if (timer.joinable()) timer.join();
  server->setControlHandler(nullptr);
  if (recorder) {
    server->setTap(nullptr);
    recorder->stop();
  }
  const auto st = replayer->stats();
  std::fprintf(stderr,
               "telesphere-robot: replayed %llu stereo frames, %llu states, %llu telemetry batches, %llu health "
               "(%llu passes; latest message %.1f ms after its time)\n",
               static_cast<unsigned long long>(st.frames), static_cast<unsigned long long>(st.states),
               static_cast<unsigned long long>(st.telemetry), static_cast<unsigned long long>(st.health),
               static_cast<unsigned long long>(st.loops), st.late_ms_max);
  if (!whole) {
    std::cerr << "telesphere-robot: --replay stopped: " << error << '\n';
    return 3;
  }
  return 0;
}

}  // namespace telesphere::app
