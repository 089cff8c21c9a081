// SPDX-License-Identifier: MIT
/// @brief Recording and replaying sessions through `telesphere-robot` on loopback (issue #18): a
///        console's recording requests (start, refusals, stop) and a study trial's indicator
///        against a real robot process with --record-dir; health reports the recording; the files
///        are whole MCAP recordings holding the frames. Then `telesphere-robot --replay` serves one
///        of them to a LinkClient, which receives the recorded JPEG bytes, and refuses control.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <thread>

#include "robot/link/link_client.h"
#include "robot/record/foxglove_compressed_image.pb.h"
#include "robot/record/mcap_reader.h"
#include "tests/console/sim_robot_process.h"

namespace {

namespace link = telesphere::link;
namespace record = telesphere::record;
constexpr int kPort = 28180, kReplayPort = 28190;
const std::string kBin = TELESPHERE_BINARY_DIR "/bin/";

class RobotRecording : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("telesphere-recording-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::filesystem::path dir_;
};

link::proto::ControlReply ask(link::LinkClient& client, link::proto::ControlRequest request) {
  const auto reply = client.request(std::move(request), std::chrono::seconds(10));
  EXPECT_TRUE(reply) << "no reply";
  return reply ? *reply : link::proto::ControlReply{};
}

link::proto::ControlRequest recordingRequest(bool start, const std::string& name = "") {
  link::proto::ControlRequest r;
  r.mutable_recording()->set_start(start);
  r.mutable_recording()->set_name(name);
  return r;
}

/// Messages per topic, and every left JPEG, of a whole recording.
std::map<std::string, int> topics(const std::string& path, std::vector<std::string>* left_jpegs = nullptr) {
  std::map<std::string, int> counts;
  std::string error;
  const auto reader = record::McapReader::open(path, &error);
  EXPECT_TRUE(reader) << error;
  if (!reader) return counts;
  EXPECT_TRUE(reader->forEachMessage(
      [&](const record::McapMessageView& m) {
        ++counts[m.channel->topic];
        if (left_jpegs && m.channel->topic == "/stereo/left/compressed") {
          foxglove::CompressedImage image;
          image.ParseFromArray(m.data, static_cast<int>(m.size));
          left_jpegs->push_back(image.data());
        }
        return true;
      },
      &error))
      << error;
  return counts;
}

TEST_F(RobotRecording, TheConsoleAndATrialRecordAndTheReplayServesItAgain) {
  const std::string records = (dir_ / "recordings").string();
  std::string error;
  const pid_t robot = telesphere::test::spawnRobot(
      {kBin + "telesphere-robot", "--insecure", "--sim", "--port", std::to_string(kPort), "--size", "320x180", "--fps", "15",
       "--stats-period", "0", "--preview-rate", "0", "--record-dir", records, "--record-compression", "lz4"},
      (dir_ / "robot.log").string(), &error);
  ASSERT_GT(robot, 0) << error;
  {
    link::LinkEndpoints endpoints;
    endpoints.base_port = kPort;
    link::LinkClient client(endpoints);
    // The console's record button: start, a second start refused, stop.
    auto reply = ask(client, recordingRequest(true, "supervisor-1"));
    EXPECT_TRUE(reply.ok()) << reply.error();
    EXPECT_TRUE(reply.recording().active());
    EXPECT_TRUE(reply.recording().available());
    EXPECT_NE(reply.recording().file().find("supervisor-1.mcap"), std::string::npos);
    reply = ask(client, recordingRequest(true, "supervisor-2"));
    EXPECT_FALSE(reply.ok());
    EXPECT_NE(reply.error().find("already recording"), std::string::npos) << reply.error();
    // Health says so while it records (published every 500 ms).
    bool seen = false;
    for (int i = 0; i < 100 && !seen; ++i) {
      const auto health = client.latestRobotHealth();
      seen = health && health->recording().active() && health->recording().messages() > 0;
      if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_TRUE(seen) << "health never showed the recording";
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // frames to record
    reply = ask(client, recordingRequest(false));
    EXPECT_TRUE(reply.ok()) << reply.error();
    EXPECT_FALSE(reply.recording().active());
    EXPECT_GT(reply.recording().messages(), 0u);
    EXPECT_EQ(reply.recording().dropped(), 0u);
    // Refusals: a stop with nothing recording, names that are not plain, a file that exists.
    EXPECT_FALSE(ask(client, recordingRequest(false)).ok());
    for (const std::string bad : {"../escape", "", ".hidden", "a/b"}) {
      reply = ask(client, recordingRequest(true, bad));
      EXPECT_FALSE(reply.ok()) << bad;
      EXPECT_NE(reply.error().find("not a plain file name"), std::string::npos) << reply.error();
    }
    reply = ask(client, recordingRequest(true, "supervisor-1"));
    EXPECT_FALSE(reply.ok());
    EXPECT_NE(reply.error().find("never overwrites"), std::string::npos) << reply.error();
    // A study trial: the indicator on with a recording name records, off stops.
    link::proto::ControlRequest on;
    on.mutable_set_trial_indicator()->set_running(true);
    on.mutable_set_trial_indicator()->set_recording_name("P01-full6d-trial1");
    reply = ask(client, on);
    EXPECT_TRUE(reply.ok()) << reply.error();
    EXPECT_TRUE(reply.recording().active()) << reply.error();
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    link::proto::ControlRequest off;
    off.mutable_set_trial_indicator()->set_running(false);
    reply = ask(client, off);
    EXPECT_TRUE(reply.ok()) << reply.error();
    EXPECT_FALSE(reply.recording().active());
    EXPECT_NE(reply.recording().file().find("P01-full6d-trial1.mcap"), std::string::npos);
  }
  telesphere::test::stopRobot(robot);
  std::vector<std::string> jpegs;
  const auto supervisor = topics(records + "/supervisor-1.mcap", &jpegs);
  EXPECT_GT(supervisor.at("/stereo/frame"), 5);
  EXPECT_EQ(supervisor.at("/stereo/frame"), supervisor.at("/stereo/left/compressed"));
  EXPECT_GT(supervisor.at("/robot/state"), 10);
  EXPECT_EQ(supervisor.at("/control/request"), 2);  // the refused second start and the stop
  const auto trial = topics(records + "/P01-full6d-trial1.mcap");
  EXPECT_GT(trial.at("/stereo/frame"), 3);
  EXPECT_FALSE(std::filesystem::exists(records + "/supervisor-2.mcap"));

  // The supervisor's recording served again; control refused.
  const pid_t replay = telesphere::test::spawnRobot(
      {kBin + "telesphere-robot", "--insecure", "--replay", records + "/supervisor-1.mcap", "--port", std::to_string(kReplayPort),
       "--loop"},
      (dir_ / "replay.log").string(), &error);
  ASSERT_GT(replay, 0) << error;
  {
    link::LinkEndpoints endpoints;
    endpoints.base_port = kReplayPort;
    link::LinkClient client(endpoints);
    std::set<std::string> recorded(jpegs.begin(), jpegs.end());
    int matched = 0;
    for (int i = 0; i < 100 && matched < 3; ++i) {
      const auto frame = client.waitForFrame(std::chrono::milliseconds(200));
      if (frame && recorded.count(std::string(frame->left_jpeg.begin(), frame->left_jpeg.end()))) ++matched;
    }
    EXPECT_EQ(matched, 3) << telesphere::test::fileText((dir_ / "replay.log").string());
    const auto reply = ask(client, recordingRequest(true, "x"));
    EXPECT_FALSE(reply.ok());
    EXPECT_NE(reply.error().find("replay"), std::string::npos) << reply.error();
  }
  telesphere::test::stopRobot(replay);
}

}  // namespace
