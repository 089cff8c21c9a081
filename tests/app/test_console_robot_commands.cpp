// SPDX-License-Identifier: MIT
/// @brief `telesphere-console status|control` against a real `telesphere-robot --sim` on loopback
///        (issue #30): the status as text and JSON, a stop and a clear-fault that waits for the
///        arm, a mode and a radius (one the robot refuses, with its reason), a scene proxy, a codec (H.264 refused
///        beside the media path), a hold released by
///        script, a recording started and stopped, bad arguments, and no robot at all.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "console/calibration/calibration_robot.h"
#include "robot/link/link_client.h"
#include "tests/console/sim_robot_process.h"

namespace {
namespace link = telesphere::link;
using telesphere::test::CommandResult;
using telesphere::test::runCommand;

constexpr int kPort = 28300;
const std::string kBin = TELESPHERE_BINARY_DIR "/bin/";

class ConsoleRobotCommands : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("telesphere-robot-commands-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_ / "recordings");
    std::string error;
    robot_pid_ = telesphere::test::spawnRobot(
        {kBin + "telesphere-robot", "--insecure", "--sim", "--port", std::to_string(kPort), "--size", "320x180", "--fps", "5",
         "--preview-rate", "0", "--stats-period", "0", "--record-dir", (dir_ / "recordings").string()},
        (dir_ / "robot.log").string(), &error);
    ASSERT_GT(robot_pid_, 0) << error;
  }
  static void TearDownTestSuite() {
    telesphere::test::stopRobot(robot_pid_);
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  static CommandResult console(const std::string& args, int port = kPort) {
    return runCommand(kBin + "telesphere-console " + args + " --insecure --robot tcp://127.0.0.1:" + std::to_string(port),
                      dir_.string());
  }
  static nlohmann::json status() {
    const CommandResult r = console("status --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out, nullptr, false);
  }
  static inline std::filesystem::path dir_;
  static inline pid_t robot_pid_ = -1;
};

TEST_F(ConsoleRobotCommands, StatusStopClearModeRadiusHoldAndRecording) {
  ASSERT_GT(robot_pid_, 0);
  CommandResult r = console("status");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("arm        ok (simulated xArm 6)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("hold       none"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("video      mjpeg"), std::string::npos) << r.out;  // the codec in use (#34)
  nlohmann::json s = status();
  ASSERT_FALSE(s.is_discarded());
  EXPECT_EQ(s["state"]["arm_ok"], true);
  EXPECT_EQ(s["health"]["recording"]["available"], true);

  r = console("control stop");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  s = status();
  EXPECT_EQ(s["state"]["arm_ok"], false);
  EXPECT_EQ(s["state"]["fault"], "arm stopped from the console");
  r = console("control clear-fault");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("arm ok"), std::string::npos) << r.out;
  EXPECT_EQ(status()["state"]["arm_ok"], true);

  r = console("control mode fixed");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(status()["health"]["settings"]["visual_mode"], "VISUAL_MODE_FIXED");
  r = console("control radius 2.5");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  r = console("control radius 0.001");
  EXPECT_EQ(r.exit_code, 5) << r.out << r.err;
  EXPECT_NE(r.out.find("refused: sphere radius"), std::string::npos) << r.out;
  // The scene proxy (#35): none chosen at first, then the session's.
  r = console("status");
  EXPECT_NE(r.out.find("scene proxy none chosen"), std::string::npos) << r.out;
  r = console("control depth-proxy grid");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(status()["health"]["settings"]["depth_proxy"], "DEPTH_PROXY_GRID");
  r = console("status");
  EXPECT_NE(r.out.find("scene proxy grid"), std::string::npos) << r.out;
  // The codec (#34): H.264 taken by this robot, which serves the UDP media path too; back to
  // MJPEG; an unknown codec never leaves the console.
  r = console("control codec h264");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(status()["health"]["settings"].value("video_codec", "VIDEO_CODEC_MJPEG"), "VIDEO_CODEC_H264");
  r = console("control codec mjpeg");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(status()["health"]["settings"].value("video_codec", "VIDEO_CODEC_MJPEG"), "VIDEO_CODEC_MJPEG");
  r = console("control codec vp9");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("mjpeg, h264 or hevc"), std::string::npos) << r.err;

  // A hold that a wizard left: released by script, and the status says so.
  link::LinkEndpoints endpoints;
  endpoints.base_port = kPort;
  link::LinkClient wizard_link(endpoints, link::LinkClient::Options{.frames = false});
  telesphere::console::calibration::CalibrationRobot wizard(wizard_link, "scripted test");
  std::string error;
  const auto T_head = wizard.headPose(std::chrono::seconds(10));
  ASSERT_TRUE(T_head);
  ASSERT_TRUE(wizard.holdHeadAt(*T_head, &error)) << error;
  r = console("status");
  EXPECT_NE(r.out.find("hold       held by scripted test, pid "), std::string::npos) << r.out;
  r = console("control release-hold");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  s = status();
  EXPECT_EQ(s["state"]["hold"]["lease"], "0");  // uint64 in protobuf's JSON is a string
  EXPECT_NE(s["state"]["hold"]["last_release"].get<std::string>().find("released by telesphere-console control"),
            std::string::npos)
      << s["state"]["hold"];

  r = console("control record start scripted-take");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("scripted-take.mcap"), std::string::npos) << r.out;
  r = console("control record start another");
  EXPECT_EQ(r.exit_code, 5) << r.out;
  r = console("control record stop");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "recordings" / "scripted-take.mcap"));
}

TEST_F(ConsoleRobotCommands, BadArgumentsAndAnAbsentRobot) {
  CommandResult r = console("control mode sideways");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("full6d, orientation3d or fixed"), std::string::npos) << r.err;
  r = console("control dance");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("unknown action 'dance'"), std::string::npos) << r.err;
  r = console("control radius far");
  EXPECT_EQ(r.exit_code, 1);
  r = console("control depth-proxy sphere");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("fixed, radius or grid"), std::string::npos) << r.err;
  r = console("status --wait 1", kPort + 40);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("did not answer"), std::string::npos) << r.err;
  r = console("control stop --wait 1", kPort + 40);
  EXPECT_EQ(r.exit_code, 3);
}

}  // namespace
