// SPDX-License-Identifier: MIT
/// @brief A calibration hold ends with its holder, through real processes (issue #30): a headless
///        `telesphere-console calibrate handeye --auto` holds the head of a real `telesphere-robot
///        --sim` (the hand-eye pattern); killed with SIGKILL it can release nothing, and the robot
///        releases the head by itself within its lease (2 s) and says why; stopped with SIGTERM
///        it releases the head itself and exits 130.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "robot/link/link_client.h"
#include "tests/console/sim_robot_process.h"
#include "tests/eventually.h"

namespace {
namespace link = telesphere::link;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr int kPort = 28280;
const std::string kBin = TELESPHERE_BINARY_DIR "/bin/";
const std::string kSrc = TELESPHERE_SOURCE_DIR "/";

class CalibrationHold : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("telesphere-hold-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    std::string error;
    robot_pid_ = telesphere::test::spawnRobot(
        {kBin + "telesphere-robot", "--insecure", "--sim", "--port", std::to_string(kPort), "--size", "320x180", "--fps", "5",
         "--preview-rate", "0", "--stats-period", "0"},
        (dir_ / "robot.log").string(), &error);
    ASSERT_GT(robot_pid_, 0) << error;
  }
  static void TearDownTestSuite() {
    telesphere::test::stopRobot(robot_pid_);
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  /// The headless hand-eye wizard against the robot; its pid once the robot shows its hold.
  pid_t startWizard(const std::string& log) {
    std::string error;
    const pid_t pid = telesphere::test::spawnRobot(
        {kBin + "telesphere-console", "calibrate", "handeye", "--insecure", "--auto", "--robot",
         "tcp://127.0.0.1:" + std::to_string(kPort), "--calib", kSrc + "calib/data/sim_calibration.yaml", "--out",
         (dir_ / "unused.yaml").string(), "--time-limit", "120"},
        log, &error);
    EXPECT_GT(pid, 0) << error;
    EXPECT_TRUE(telesphere::test::eventually([&] {
      const auto s = console_.latestRobotState();
      return s && s->hold().holder().rfind("hand-eye wizard (headless), pid " + std::to_string(pid), 0) == 0;
    }, 30s)) << telesphere::test::fileText(log) << "\n--- robot\n" << robotLog();
    return pid;
  }
  /// Seconds from now until the robot's state shows no hold (-1: not within `limit`).
  double secondsUntilReleased(std::chrono::milliseconds limit) {
    const auto t0 = Clock::now();
    if (!telesphere::test::eventually([&] {
          const auto s = console_.latestRobotState();
          return s && s->hold().lease() == 0;
        }, limit))
      return -1;
    return std::chrono::duration<double>(Clock::now() - t0).count();
  }
  static std::string robotLog() { return telesphere::test::fileText((dir_ / "robot.log").string()); }

  link::LinkClient console_{[] {
                              link::LinkEndpoints e;
                              e.base_port = kPort;
                              return e;
                            }(),
                            link::LinkClient::Options{.frames = false}};
  static inline std::filesystem::path dir_;
  static inline pid_t robot_pid_ = -1;
};

TEST_F(CalibrationHold, AKilledWizardsHoldEndsWithinItsLease) {
  ASSERT_GT(robot_pid_, 0);
  const pid_t wizard = startWizard((dir_ / "wizard-kill.log").string());
  ASSERT_GT(wizard, 0);
  ASSERT_EQ(kill(wizard, SIGKILL), 0);
  int status = 0;
  waitpid(wizard, &status, 0);
  const double released_s = secondsUntilReleased(10s);
  const auto s = console_.latestRobotState();
  std::printf("killed wizard: the robot released the head %.2f s later (lease %.1f s)\n", released_s,
              s ? s->hold().lease_s() : 0.0);
  ASSERT_GE(released_s, 0) << "still held 10 s after its holder died\n" << robotLog();
  EXPECT_LT(released_s, 2.6);  // the lease, plus a renewal period that was under way and a tick
  EXPECT_GT(released_s, 1.0) << "released before the lease ran out: by whom?";
  ASSERT_TRUE(s);
  EXPECT_NE(s->hold().last_release().find("not renewed"), std::string::npos) << s->hold().last_release();
  EXPECT_FALSE(s->calibration_hold());
}

TEST_F(CalibrationHold, AnInterruptedWizardReleasesTheHeadItselfAndExits130) {
  ASSERT_GT(robot_pid_, 0);
  const std::string log = (dir_ / "wizard-term.log").string();
  const pid_t wizard = startWizard(log);
  ASSERT_GT(wizard, 0);
  ASSERT_EQ(kill(wizard, SIGTERM), 0);
  const auto t0 = Clock::now();
  int status = 0;
  pid_t done = 0;
  while ((done = waitpid(wizard, &status, WNOHANG)) == 0 && Clock::now() - t0 < 20s) std::this_thread::sleep_for(10ms);
  ASSERT_EQ(done, wizard) << "the wizard did not end within 20 s of SIGTERM";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130) << telesphere::test::fileText(log);
  EXPECT_NE(telesphere::test::fileText(log).find("interrupted: stopped and released the head"), std::string::npos)
      << telesphere::test::fileText(log);
  const double released_s = secondsUntilReleased(3s);
  ASSERT_GE(released_s, 0) << robotLog();
  EXPECT_LT(released_s, 0.5) << "released by the lease, not by the wizard";
  const auto s = console_.latestRobotState();
  ASSERT_TRUE(s);
  EXPECT_NE(s->hold().last_release().find("released by its holder"), std::string::npos) << s->hold().last_release();
}

}  // namespace
