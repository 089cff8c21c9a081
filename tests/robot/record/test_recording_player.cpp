// SPDX-License-Identifier: MIT
/// @brief Replaying a recorded session onto a real LinkServer: the replay, itself recorded by a
///        second LinkRecorder, holds the same frames (JPEG bytes, sequences), states and
///        telemetry in order, with robot-clock stamps moved to the replay's start and their
///        spacing of their messages divided by the rate, what each measures inside itself kept; a LinkClient on loopback receives the frames. The stamp
///        mapping on its own: robot-clock fields moved, operator-clock fields and durations not,
///        unset (0) stays unset.
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "robot/link/link_client.h"
#include "robot/link/link_server.h"
#include "robot/record/foxglove_compressed_image.pb.h"
#include "robot/record/link_recorder.h"
#include "robot/record/recording_player.h"

namespace telesphere::record {
namespace {

namespace proto = link::proto;
constexpr int kRecordPort = 28160, kReplayPort = 28170;

std::filesystem::path tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("telesphere-replay-" + std::to_string(getpid()) + "-" + name);
}

// A message logged at 1.0 s replayed first, at 2×, from 50 s on: its robot-clock stamps move by
// the one shift of its log time (49 s), so what it measures inside itself stays as recorded.
TEST(SessionReplay, RobotClockStampsMoveWithTheirMessageOperatorClockAndDurationsStay) {
  proto::RobotTelemetry t;
  auto* tick = t.add_ticks();
  tick->set_t_ns(1'000'000'000);
  tick->set_target_t_ns(1'010'000'000);  // robot clock (the sender's sample time mapped by its offset)
  tick->set_joint_state_ns(0);           // unset stays unset
  auto* frame = t.add_frames();
  frame->set_capture_ns(1'200'000'000);
  proto::StereoFrame f;
  f.mutable_left()->set_capture_ns(1'100'000'000);
  f.mutable_stamps()->set_received_ns(777);  // operator clock: not the robot's
  const std::int64_t shift = 49'000'000'000;
  shiftRobotClockStamps(&t, shift);
  shiftRobotClockStamps(&f, shift);
  EXPECT_EQ(t.ticks(0).t_ns(), 50'000'000'000);
  EXPECT_EQ(t.ticks(0).target_t_ns(), 50'010'000'000);  // 10 ms after the tick, as recorded
  EXPECT_EQ(t.ticks(0).joint_state_ns(), 0);
  EXPECT_EQ(t.frames(0).capture_ns(), 50'200'000'000);
  EXPECT_EQ(f.left().capture_ns(), 50'100'000'000);
  EXPECT_EQ(f.stamps().received_ns(), 777);
  proto::RobotHealth health;
  health.set_head_target_age_ns(12'345);  // a duration
  health.set_t_ns(1'000'000'000);
  shiftRobotClockStamps(&health, shift);
  EXPECT_EQ(health.head_target_age_ns(), 12'345);
  EXPECT_EQ(health.t_ns(), 50'000'000'000);
}

struct Recorded {
  std::vector<proto::StereoFrame> frames;
  std::vector<std::int64_t> frame_log_ns;  ///< each frame's log time (UTC; differences are the robot's)
  std::vector<std::string> left_jpegs;
  std::vector<proto::RobotState> states;
  std::vector<proto::RobotTelemetry> telemetry;
};

Recorded readRecording(const std::string& path) {
  Recorded r;
  std::string error;
  const auto reader = McapReader::open(path, &error);
  EXPECT_TRUE(reader) << error;
  if (!reader) return r;
  EXPECT_TRUE(reader->forEachMessage(
      [&](const McapMessageView& m) {
        const int n = static_cast<int>(m.size);
        if (m.channel->topic == "/stereo/frame") {
          r.frames.emplace_back().ParseFromArray(m.data, n);
          r.frame_log_ns.push_back(static_cast<std::int64_t>(m.log_time_ns));
        }
        if (m.channel->topic == "/stereo/left/compressed") {
          foxglove::CompressedImage image;
          image.ParseFromArray(m.data, n);
          r.left_jpegs.push_back(image.data());
        }
        if (m.channel->topic == "/robot/state") r.states.emplace_back().ParseFromArray(m.data, n);
        if (m.channel->topic == "/robot/telemetry") r.telemetry.emplace_back().ParseFromArray(m.data, n);
        return true;
      },
      &error))
      << error;
  return r;
}

TEST(SessionReplay, TheReplayIsTheRecordingAgainMovedToNow) {
  const std::string recording = tempFile("recording.mcap").string(), replayed = tempFile("replayed.mcap").string();
  std::string error;
  // A session: 30 frames 20 ms apart with distinct JPEG bytes, a state per frame, telemetry.
  {
    link::LinkEndpoints endpoints;
    endpoints.base_port = kRecordPort;
    link::LinkServer server(endpoints);
    auto recorder = LinkRecorder::start(recording, {}, &error);
    ASSERT_TRUE(recorder) << error;
    server.setTap(recorder);
    const std::int64_t t0 = link::linkNowNs();
    for (int i = 0; i < 30; ++i) {
      proto::StereoFrame frame;
      frame.set_sequence(std::uint64_t(i + 1));
      frame.mutable_left()->set_capture_ns(t0 + i * 20'000'000LL);
      frame.mutable_right()->set_capture_ns(t0 + i * 20'000'000LL);
      for (auto* image : {frame.mutable_left(), frame.mutable_right()}) {
        image->set_width(64);
        image->set_height(48);
      }
      auto jpeg = std::make_shared<std::vector<std::uint8_t>>(1000 + std::size_t(i), std::uint8_t(i));
      server.publishStereoFrame(frame, jpeg, jpeg);
      proto::RobotState state;
      state.set_t_ns(t0 + i * 20'000'000LL);
      server.publishRobotState(state);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the recorded pace
    }
    proto::RobotTelemetry telemetry;
    telemetry.set_batch(1);
    telemetry.add_ticks()->set_t_ns(t0);
    server.publishTelemetry(telemetry);
    server.setTap(nullptr);
    ASSERT_TRUE(recorder->stop());
  }
  const Recorded original = readRecording(recording);
  ASSERT_EQ(original.frames.size(), 30u);

  // Replayed twice as fast onto another server, recorded again; a client listens on loopback.
  link::LinkEndpoints endpoints;
  endpoints.base_port = kReplayPort;
  link::LinkServer server(endpoints);
  link::LinkClient client(endpoints);
  // PUB/SUB: a subscriber hears only what is sent after it joined. Wait until it hears the frame
  // socket (a frame sent before the replay, sequence 0, not recorded).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  bool heard = false;
  proto::StereoFrame probe;
  for (auto* image : {probe.mutable_left(), probe.mutable_right()}) {
    image->set_width(64);
    image->set_height(48);
  }
  while (!heard && std::chrono::steady_clock::now() < deadline) {
    server.publishStereoFrame(probe, std::make_shared<std::vector<std::uint8_t>>(1, 0),
                              std::make_shared<std::vector<std::uint8_t>>(1, 0));
    heard = client.waitForFrame(std::chrono::milliseconds(50)).has_value();
  }
  ASSERT_TRUE(heard);
  auto replayer = RecordingPlayer::open(recording, &error);
  ASSERT_TRUE(replayer) << error;
  auto recorder = LinkRecorder::start(replayed, {}, &error);
  ASSERT_TRUE(recorder) << error;
  server.setTap(recorder);
  std::atomic<bool> stop{false};
  RecordingPlayerOptions options;
  options.rate = 2.0;
  std::optional<link::ReceivedFrame> received;
  std::thread listener([&] {
    while (!stop && !received) {
      auto f = client.waitForFrame(std::chrono::milliseconds(100));
      if (f && f->frame.sequence() > 0) received = std::move(f);
    }
  });
  const std::int64_t replay_start = link::linkNowNs();
  ASSERT_TRUE(replayer->run(server, options, stop, &error)) << error;
  stop = true;
  listener.join();
  server.setTap(nullptr);
  ASSERT_TRUE(recorder->stop());
  const RecordingPlayerStats stats = replayer->stats();
  EXPECT_EQ(stats.frames, 30u);
  EXPECT_EQ(stats.states, 30u);
  EXPECT_EQ(stats.telemetry, 1u);
  EXPECT_EQ(stats.loops, 1u);
  EXPECT_EQ(stats.skipped, 0u);

  const Recorded again = readRecording(replayed);
  ASSERT_EQ(again.frames.size(), 30u);
  ASSERT_EQ(again.left_jpegs.size(), 30u);
  ASSERT_EQ(again.states.size(), 30u);
  const std::int64_t first = original.frames[0].left().capture_ns();
  for (std::size_t i = 0; i < 30; ++i) {
    EXPECT_EQ(again.frames[i].sequence(), original.frames[i].sequence());
    EXPECT_EQ(again.left_jpegs[i], original.left_jpegs[i]) << "frame " << i;
    // Moved to the replay's start with its message: the log times' spacing halved, each frame's
    // capture → send latency as recorded (±2 ns of rounding).
    const std::int64_t spacing = again.frames[i].left().capture_ns() - again.frames[0].left().capture_ns();
    const double log_spacing = double(original.frame_log_ns[i] - original.frame_log_ns[0]);
    EXPECT_NEAR(double(spacing), double(original.frames[i].left().capture_ns() - first) - log_spacing / 2.0, 2.0);
    EXPECT_GE(again.frames[i].left().capture_ns(), replay_start - 1'000'000'000);
  }
  EXPECT_EQ(again.telemetry.size(), 1u);
  ASSERT_TRUE(received);
  const auto i = std::size_t(received->frame.sequence() - 1);
  ASSERT_LT(i, 30u);
  EXPECT_EQ(std::string(received->left_jpeg.begin(), received->left_jpeg.end()), original.left_jpegs[i]);
  std::filesystem::remove(recording);
  std::filesystem::remove(replayed);
}

TEST(SessionReplay, AFileThatIsNotARecordingIsRefused) {
  std::string error;
  EXPECT_FALSE(RecordingPlayer::open(tempFile("missing.mcap").string(), &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::record
