// SPDX-License-Identifier: MIT
/// @brief `telesphere-console calibrate handeye --auto` against a real `telesphere-robot --sim
///        --sim-manipulator` on loopback (issue #15): the robot believes
///        calib/data/sim_calibration.yaml (another T_flange_cam_l, no manipulator transforms)
///        while its synthetic cameras and manipulator really have
///        tests/console/data/handeye_truth.yaml (--sim-truth); the headless procedure must
///        recover T_flange_cam_l, T_robot_mount and T_wrist_marker within bounds from its own
///        standard deviations (and the start's T_flange_cam_l must lie outside them). With the
///        head held still the set is degenerate: refused, exit 2 with the reason, no file.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "calib/calibration_file.h"
#include "robot/link/link_client.h"
#include "tests/console/sim_robot_process.h"
#include "tests/console/still_robot_pose.h"

namespace {
namespace calib = telesphere::calib;
namespace link = telesphere::link;

constexpr int kPort = 28010;
const std::string kBin = TELESPHERE_BINARY_DIR "/bin/";
const std::string kSrc = TELESPHERE_SOURCE_DIR "/";

using telesphere::test::CommandResult;
using telesphere::test::runCommand;
using telesphere::test::distanceMmDeg;
using telesphere::test::RobotFrame;
using telesphere::test::currentRobotPose;
using telesphere::test::stillRobotPose;

class CalibrateHandEye : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("telesphere-handeye-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    std::string error;
    robot_pid_ = telesphere::test::spawnRobot(
        {TELESPHERE_FIXTURE_BIN_DIR "/telesphere-robot", "--insecure", "--sim", "--sim-manipulator", "--port", std::to_string(kPort), "--size", "1280x720",
         "--fps", "5", "--still-timeout-ms", "20000", "--sim-truth", kSrc + "tests/console/data/handeye_truth.yaml",
         "--preview-rate", "0", "--stats-period", "0"},
        (dir_ / "robot.log").string(), &error);
    ASSERT_GT(robot_pid_, 0) << error;
    probe_ = std::make_unique<link::LinkClient>(link::LinkEndpoints{.host = "127.0.0.1", .base_port = kPort, .credentials = {}},
                                                link::LinkClient::Options{.frames = false});
  }
  static void TearDownTestSuite() {
    probe_.reset();
    telesphere::test::stopRobot(robot_pid_);
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  static std::string calibrate(const std::string& extra) {
    return kBin + "telesphere-console calibrate handeye --insecure --auto --robot tcp://127.0.0.1:" + std::to_string(kPort) +
           " --calib " + kSrc + "calib/data/sim_calibration.yaml --json " + extra;
  }
  /// The robot's own account, for a failure message (the folder is gone after the suite).
  static std::string robotLogTail() {
    const std::string log = telesphere::test::fileText((dir_ / "robot.log").string());
    return log.size() > 6000 ? log.substr(log.size() - 6000) : log;
  }
  static inline std::filesystem::path dir_;
  static inline pid_t robot_pid_ = -1;
  static inline std::unique_ptr<link::LinkClient> probe_;
};

double rotationDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

TEST_F(CalibrateHandEye, RecoversTheThreeTransformsFromAWrongStart) {
  ASSERT_GT(robot_pid_, 0);
  // The flange, not the head: --apply changes the head frame, not where the arm stands.
  const auto T_robot_flange_before = currentRobotPose(*probe_, RobotFrame::kFlange);
  ASSERT_TRUE(T_robot_flange_before) << "the robot reports no flange pose";
  const std::string out_file = (dir_ / "handeye.yaml").string();
  // Room beyond the default 60 samples: which poses the simulated manipulator is in when the run
  // starts shifts by the few hundred ms the probe above takes. With cornerSubPix's marker corners
  // some phases needed 60–70 samples for T_robot_mount's σ (2.05–2.07 mm at 60 in 4 of 22 runs; the
  // rule is 2.0); with the edge-refined corners 8 of 8 runs were done within 21–43 (calib/README.md).
  const CommandResult r = runCommand(calibrate("--apply --max-samples 90 --out " + out_file), dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err.substr(0, 3000) << "\n[…]\n"
                            << r.err.substr(r.err.size() > 3000 ? r.err.size() - 3000 : 0)
                            << "\n--- robot log (last 6000 characters):\n" << robotLogTail();
  const auto T_robot_flange_after = stillRobotPose(*probe_, RobotFrame::kFlange);
  ASSERT_TRUE(T_robot_flange_after);
  const auto [moved_mm, turned_deg] = distanceMmDeg(*T_robot_flange_before, *T_robot_flange_after);
  std::printf("flange after the run: %.2f mm, %.3f° from where it started\n", moved_mm, turned_deg);
  EXPECT_LT(moved_mm, 2.0) << "the run must leave the arm where it found it";
  EXPECT_LT(turned_deg, 0.5);
  EXPECT_NE(r.err.find("applied: the robot uses calibration generation 2 (was 1)"), std::string::npos)
      << r.err.substr(0, 6000);
  const nlohmann::json figures = nlohmann::json::parse(r.out);
  EXPECT_TRUE(figures["done"].get<bool>());
  EXPECT_GE(figures["samples"].get<int>(), 15);
  std::printf("stills %d, samples %d, refused %d, too close %d, outliers %d; head/wrist axis spread %.1f°/%.1f°; "
              "first sample to result %.1f s\n",
              figures["stills"].get<int>(), figures["samples"].get<int>(), figures["stills_refused"].get<int>(),
              figures["stills_too_close"].get<int>(), figures["outliers_removed"].get<int>(),
              figures["head_axis_spread_deg"].get<double>(), figures["wrist_axis_spread_deg"].get<double>(),
              figures["first_sample_to_result_s"].get<double>());
  for (const auto& step : figures["history"]) {
    if (!step["ok"].get<bool>()) continue;
    // A step's σ is absent where the covariance was rank deficient (the JSON says so by omission).
    const nlohmann::json& pose = step["T_flange_cam_l"];
    if (pose.contains("sigma_t_mm"))
      std::printf("  %2d samples: RMS %.3f px, T_flange_cam_l σ_t (%.2f, %.2f, %.2f) mm\n", step["samples"].get<int>(),
                  step["rms_px"].get<double>(), pose["sigma_t_mm"][0].get<double>(),
                  pose["sigma_t_mm"][1].get<double>(), pose["sigma_t_mm"][2].get<double>());
    else
      std::printf("  %2d samples: RMS %.3f px, T_flange_cam_l σ not computed\n", step["samples"].get<int>(),
                  step["rms_px"].get<double>());
  }

  const auto truth = calib::loadCalibrationFile(kSrc + "tests/console/data/handeye_truth.yaml");
  const auto start = calib::loadCalibrationFile(kSrc + "calib/data/sim_calibration.yaml");
  const auto recovered = calib::loadCalibrationFile(out_file);
  ASSERT_TRUE(truth && start && recovered) << (recovered ? "" : recovered.error().describe());
  ASSERT_TRUE(recovered->T_flange_cam_l && recovered->T_robot_mount && recovered->T_wrist_marker);
  // The intrinsics and the stereo extrinsic are those of --calib, untouched.
  EXPECT_TRUE(recovered->T_cam_l_cam_r->isApprox(*start->T_cam_l_cam_r, 1e-9));
  EXPECT_EQ(recovered->cameras[0].width, 3840);
  struct Check {
    const char* name;
    Eigen::Isometry3d got, want;
  };
  for (const Check& c : {Check{"T_flange_cam_l", *recovered->T_flange_cam_l, *truth->T_flange_cam_l},
                         Check{"T_robot_mount", *recovered->T_robot_mount, *truth->T_robot_mount},
                         Check{"T_wrist_marker", *recovered->T_wrist_marker, *truth->T_wrist_marker}}) {
    const nlohmann::json& f = figures[c.name];
    ASSERT_TRUE(f.contains("sigma_t_mm") && f.contains("sigma_r_deg")) << c.name << ": the done rule needs σ";
    const Eigen::Vector3d sigma_mm(f["sigma_t_mm"][0].get<double>(), f["sigma_t_mm"][1].get<double>(),
                                   f["sigma_t_mm"][2].get<double>());
    const Eigen::Vector3d sigma_deg(f["sigma_r_deg"][0].get<double>(), f["sigma_r_deg"][1].get<double>(),
                                    f["sigma_r_deg"][2].get<double>());
    const double dt_mm = (c.got.translation() - c.want.translation()).norm() * 1e3;
    const double dr_deg = rotationDeg(c.got, c.want);
    std::printf("%-15s %.2f mm, %.3f° from the truth; |σ| %.2f mm, %.3f°\n", c.name, dt_mm, dr_deg, sigma_mm.norm(),
                sigma_deg.norm());
    // 5|σ| from the solve's own covariance, plus what the detector's corner bias adds at the
    // simulated resolution (0.5 mm, 0.05°).
    EXPECT_LT(dt_mm, 5.0 * sigma_mm.norm() + 0.5) << c.name;
    EXPECT_LT(dr_deg, 5.0 * sigma_deg.norm() + 0.05) << c.name;
  }
  // --apply: the robot uses the recovered T_flange_cam_l now, with its own cameras.
  {
    link::LinkEndpoints endpoints;
    endpoints.base_port = kPort;
    link::LinkClient client(endpoints);
    link::proto::ControlRequest get;
    get.set_get_calibration(true);
    const auto reply = client.request(get, std::chrono::seconds(5));
    ASSERT_TRUE(reply && reply->ok());
    EXPECT_EQ(reply->calibration().generation(), 2u);
    const auto in_use = calib::parseCalibration(reply->calibration().yaml(), "robot");
    ASSERT_TRUE(in_use) << in_use.error().describe();
    EXPECT_TRUE(in_use->T_flange_cam_l->isApprox(*recovered->T_flange_cam_l, 1e-12));
    EXPECT_EQ(in_use->cameras[0].camera.params(), start->cameras[0].camera.params());
  }
  // The start's T_flange_cam_l lies outside those bounds: the check can fail.
  const nlohmann::json& f = figures["T_flange_cam_l"];
  const double start_dt_mm = (start->T_flange_cam_l->translation() - truth->T_flange_cam_l->translation()).norm() * 1e3;
  EXPECT_GT(start_dt_mm, 5.0 * Eigen::Vector3d(f["sigma_t_mm"][0].get<double>(), f["sigma_t_mm"][1].get<double>(),
                                               f["sigma_t_mm"][2].get<double>())
                                       .norm() +
                             0.5);
}

TEST_F(CalibrateHandEye, AHeadHeldStillIsRefusedAsDegenerate) {
  ASSERT_GT(robot_pid_, 0);
  const std::string out_file = (dir_ / "never.yaml").string();
  const CommandResult r = runCommand(calibrate("--pattern-deg 0 --max-samples 8 --out " + out_file), dir_.string());
  EXPECT_EQ(r.exit_code, 2) << r.err.substr(0, 4000);
  EXPECT_NE(r.err.find("rotation axes spread: head"), std::string::npos) << r.err.substr(0, 4000);
  EXPECT_FALSE(std::filesystem::exists(out_file));
  const nlohmann::json figures = nlohmann::json::parse(r.out);
  EXPECT_FALSE(figures["done"].get<bool>());
  EXPECT_LT(figures["head_axis_spread_deg"].get<double>(), 1.0);
  ASSERT_FALSE(figures["history"].empty());
  const auto& last = figures["history"].back();
  EXPECT_FALSE(last["ok"].get<bool>());
  EXPECT_NE(last["error"].get<std::string>().find("head arm's rotations do not separate"), std::string::npos)
      << last.dump();
}

}  // namespace
