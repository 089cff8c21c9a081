// SPDX-License-Identifier: MIT
/// @brief `telesphere-console calibrate intrinsics --auto` against a real `telesphere-robot --sim`
///        on loopback (issue #15): the robot believes calib/data/sim_calibration.yaml while its
///        synthetic cameras really have tests/console/data/calibration_truth.yaml (--sim-truth);
///        the headless procedure, started from the wrong calibration, must recover the truth
///        within bounds derived from its own standard deviations (and the start must lie outside
///        them, so the check can fail). A run that cannot meet the done rule exits 2 with the
///        reason and writes nothing; no robot exits 3. Every run leaves the head where it found
///        it (the supervisor placed the board in view there; the next run starts from it).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "robot/link/link_client.h"
#include "tests/console/sim_robot_process.h"
#include "tests/console/still_robot_pose.h"

namespace {
namespace calib = telesphere::calib;

constexpr int kPort = 27960;
const std::string kBin = TELESPHERE_BINARY_DIR "/bin/";
const std::string kSrc = TELESPHERE_SOURCE_DIR "/";

using telesphere::test::CommandResult;
using telesphere::test::runCommand;
namespace link = telesphere::link;

using telesphere::test::distanceMmDeg;
using telesphere::test::RobotFrame;
using telesphere::test::stillRobotPose;

class CalibrateIntrinsics : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("telesphere-calibrate-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    const std::string robot = TELESPHERE_FIXTURE_BIN_DIR "/telesphere-robot";  // the scenery; the console is under test
    const std::string log = (dir_ / "robot.log").string();
    std::string error;
    robot_pid_ = telesphere::test::spawnRobot(
        {robot, "--insecure", "--sim", "--port", std::to_string(kPort), "--size", "1280x720", "--fps", "5", "--still-timeout-ms", "20000",
         "--sim-truth", kSrc + "tests/console/data/calibration_truth.yaml", "--preview-rate", "0", "--stats-period", "0"},
        log, &error);
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
    return kBin + "telesphere-console calibrate intrinsics --insecure --auto --robot tcp://127.0.0.1:" + std::to_string(kPort) +
           " --initial " + kSrc + "calib/data/sim_calibration.yaml --json " + extra;
  }
  static inline std::filesystem::path dir_;
  static inline pid_t robot_pid_ = -1;
  static inline std::unique_ptr<link::LinkClient> probe_;
};

TEST_F(CalibrateIntrinsics, RecoversTheTrueIntrinsicsAndStereoExtrinsicFromAWrongStart) {
  ASSERT_GT(robot_pid_, 0);
  const auto T_robot_head_before = stillRobotPose(*probe_, RobotFrame::kHead);
  ASSERT_TRUE(T_robot_head_before) << "the robot reports no still head pose";
  const std::string out_file = (dir_ / "recovered.yaml").string();
  const CommandResult r = runCommand(calibrate("--compare-models --out " + out_file), dir_.string());
  const auto T_robot_head_after = stillRobotPose(*probe_, RobotFrame::kHead);
  ASSERT_TRUE(T_robot_head_after);
  const auto [moved_mm, turned_deg] = distanceMmDeg(*T_robot_head_before, *T_robot_head_after);
  std::printf("head after the run: %.2f mm, %.3f° from where it started\n", moved_mm, turned_deg);
  EXPECT_LT(moved_mm, 2.0) << "the run must leave the head where it found it";
  EXPECT_LT(turned_deg, 0.5);
  if (r.exit_code != 0) {  // the procedure's steps, without the solver's iterations
    std::stringstream lines(r.err);
    std::string line, steps;
    while (std::getline(lines, line))
      if (line.find("solve:") == std::string::npos) steps += line + "\n";
    FAIL() << "exit " << r.exit_code << "\n" << steps;
  }
  // At 1280×720 cam_l's 100–110° ring squeezes a tag to ~17 px: the run says it does not ask for it.
  EXPECT_NE(r.err.find("cam_l: the 100–110° ring is not required"), std::string::npos) << r.err.substr(0, 3000);
  EXPECT_EQ(r.err.find("cam_r: the 100–110° ring is not required"), std::string::npos);
  const nlohmann::json figures = nlohmann::json::parse(r.out);
  EXPECT_TRUE(figures["done"].get<bool>());
  EXPECT_TRUE(figures["head_returned"].get<bool>());
  EXPECT_LE(figures["poses_refused"].get<int>(), figures["poses_visited"].get<int>());  // targets, counted once
  EXPECT_TRUE(figures["unmet"].empty());
  EXPECT_GE(figures["samples"].get<int>(), 20);
  std::printf("samples %d (joint %d), stills %d, poses %d visited / %d refused; first sample to result %.1f s\n",
              figures["samples"].get<int>(), figures["joint_views"].get<int>(), figures["stills"].get<int>(),
              figures["poses_visited"].get<int>(), figures["poses_refused"].get<int>(),
              figures["first_sample_to_result_s"].get<double>());

  // The models compared on the same samples: the simplest within 1 px is a 6-parameter model
  // (ds or eucm); pinhole cannot use the views beyond 90° and is never preselected.
  ASSERT_EQ(figures["models"].size(), 4u);
  for (const auto& m : figures["models"]) {
    std::printf("model %-7s ok %d RMS %.3f px, %d views, %.2f s %s\n", m["model"].get<std::string>().c_str(),
                int(m["ok"].get<bool>()), m["rms_px"].get<double>(), m["views_used"].get<int>(), m["solve_s"].get<double>(),
                m["message"].get<std::string>().c_str());
    if (m["model"] == "ds") {
      EXPECT_TRUE(m["ok"].get<bool>());
      EXPECT_LT(m["rms_px"].get<double>(), 0.5);
    }
  }
  const std::string preselected = figures["preselected_model"].get<std::string>();
  EXPECT_TRUE(preselected == "ds" || preselected == "eucm") << preselected;

  const auto truth = calib::loadCalibrationFile(kSrc + "tests/console/data/calibration_truth.yaml");
  const auto start = calib::loadCalibrationFile(kSrc + "calib/data/sim_calibration.yaml");
  const auto recovered = calib::loadCalibrationFile(out_file);
  ASSERT_TRUE(truth && start && recovered) << (recovered ? "" : recovered.error().describe());
  ASSERT_EQ(recovered->cameras.size(), 2u);
  ASSERT_TRUE(recovered->T_flange_cam_l);  // kept from --initial, so the robot can load the file
  std::string error;
  for (int c = 0; c < 2; ++c) {
    const auto& got = recovered->cameras[std::size_t(c)];
    const auto want = calib::atResolution(truth->cameras[std::size_t(c)], got.width, got.height, &error);
    const auto was = calib::atResolution(start->cameras[std::size_t(c)], got.width, got.height, &error);
    ASSERT_TRUE(want && was) << error;
    const nlohmann::json& cam = figures["cameras"][got.label];
    const Eigen::VectorXd p = got.camera.params(), t = want->camera.params(), s = was->camera.params();
    const auto names = calib::GenericCamera::paramNames("ds");
    int start_outside = 0;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const double sigma = cam["stddev"][std::string(names[i])].get<double>();
      const double bound = 5.0 * sigma;  // a 5σ bound from the solve's own covariance
      EXPECT_LE(std::abs(p[Eigen::Index(i)] - t[Eigen::Index(i)]), bound)
          << got.label << " " << names[i] << ": " << p[Eigen::Index(i)] << " vs true " << t[Eigen::Index(i)];
      if (std::abs(s[Eigen::Index(i)] - t[Eigen::Index(i)]) > bound) ++start_outside;
      std::printf("%s %-5s recovered %12.5f true %12.5f start %12.5f σ %.5f\n", got.label.c_str(),
                  std::string(names[i]).c_str(), p[Eigen::Index(i)], t[Eigen::Index(i)], s[Eigen::Index(i)], sigma);
    }
    EXPECT_EQ(start_outside, int(names.size())) << "the start must be told apart from the truth in every parameter";
  }
  const Eigen::Isometry3d& T = *recovered->T_cam_l_cam_r;
  const Eigen::Isometry3d& T_true = *truth->T_cam_l_cam_r;
  const double dt_mm = (T.translation() - T_true.translation()).norm() * 1000.0;
  const double dr_deg = Eigen::AngleAxisd(T.linear().transpose() * T_true.linear()).angle() * 180.0 / M_PI;
  const double start_dr_deg = Eigen::AngleAxisd(start->T_cam_l_cam_r->linear().transpose() * T_true.linear()).angle() * 180 / M_PI;
  std::printf("T_cam_l_cam_r: %.2f mm, %.4f° from the truth (start %.2f mm, %.3f°)\n", dt_mm, dr_deg,
              (start->T_cam_l_cam_r->translation() - T_true.translation()).norm() * 1000.0, start_dr_deg);
  // Per axis within 5σ of the solve's own covariance, as the intrinsics above: the stereo
  // extrinsic's accuracy depends on the views the run happened to collect (a fixed 1.5 mm failed
  // one CI run at 1.76 mm).
  ASSERT_TRUE(figures["T_cam_l_cam_r"].contains("stddev")) << figures["T_cam_l_cam_r"].dump();
  const nlohmann::json& sd = figures["T_cam_l_cam_r"]["stddev"];
  const Eigen::AngleAxisd turn(T.linear() * T_true.linear().transpose());  // about cam_l's axes
  const Eigen::Vector3d dr = turn.angle() * turn.axis() * 180 / M_PI;
  const Eigen::Vector3d dt = T.translation() - T_true.translation();
  int start_t_outside = 0;
  for (int i = 0; i < 3; ++i) {
    const double sigma_t = sd["t_m"][i].get<double>(), sigma_r = sd["r_deg"][i].get<double>();
    std::printf("T_cam_l_cam_r axis %d: t %+.3f mm (σ %.3f), r %+.4f° (σ %.4f)\n", i, dt[i] * 1e3, sigma_t * 1e3, dr[i],
                sigma_r);
    EXPECT_LE(std::abs(dt[i]), 5 * sigma_t) << "translation axis " << i;
    EXPECT_LE(std::abs(dr[i]), 5 * sigma_r) << "rotation axis " << i;
    start_t_outside += std::abs(start->T_cam_l_cam_r->translation()[i] - T_true.translation()[i]) > 5 * sigma_t;
  }
  EXPECT_GT(start_t_outside, 0) << "the start's translation must be told apart from the truth";
  EXPECT_GT(start_dr_deg, 0.05);
}

TEST_F(CalibrateIntrinsics, ExitsTwoWithTheReasonWhenTheDoneRuleCannotBeMet) {
  ASSERT_GT(robot_pid_, 0);
  const std::string out_file = (dir_ / "never.yaml").string();
  const CommandResult r = runCommand(calibrate("--max-views 4 --out " + out_file), dir_.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the head is back at its start pose"), std::string::npos) << r.err.substr(0, 3000);
  EXPECT_NE(r.err.find("the done rule is not met: 4 of 20 views"), std::string::npos) << r.err.substr(0, 3000);
  EXPECT_FALSE(std::filesystem::exists(out_file));
  const nlohmann::json figures = nlohmann::json::parse(r.out);
  EXPECT_FALSE(figures["done"].get<bool>());
  EXPECT_EQ(figures.value("samples", -1), 4);
}

// Views that meet the rule but a solve that misses a σ bound: one more ring of views, with the
// head still held, and the solve again (a Release run here missed σ(fx) 0.97 px by 0.012 px).
// A bound of 0.05 % of f is out of reach: the run ends with exit 2, but only after the top-up.
TEST_F(CalibrateIntrinsics, ATightSigmaBoundAsksForMoreViewsBeforeItGivesUp) {
  ASSERT_GT(robot_pid_, 0);
  const std::string out_file = (dir_ / "tight.yaml").string();
  const CommandResult r = runCommand(calibrate("--max-focal-std 0.05 --max-views 28 --out " + out_file), dir_.string());
  EXPECT_EQ(r.exit_code, 2) << r.err.substr(0, 3000);
  const std::size_t more = r.err.find("the solve misses the rule");
  ASSERT_NE(more, std::string::npos) << r.err.substr(0, 3000);
  EXPECT_NE(r.err.find("σ(fx)", more), std::string::npos);
  EXPECT_NE(r.err.find("solving again", more), std::string::npos);
  EXPECT_NE(r.err.find("the head is back at its start pose", more), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out_file));
  const nlohmann::json figures = nlohmann::json::parse(r.out);
  EXPECT_FALSE(figures["done"].get<bool>());
  EXPECT_TRUE(figures["head_returned"].get<bool>());
  EXPECT_GT(figures["samples"].get<int>(), 20);  // the rule's 20, then the top-up's
  EXPECT_LE(figures["samples"].get<int>(), 28);
  std::printf("tight σ bound: %d samples, exit %d\n", figures["samples"].get<int>(), r.exit_code);
}

TEST_F(CalibrateIntrinsics, ExitsThreeWhenNoRobotAnswers) {
  const CommandResult r = runCommand(kBin + "telesphere-console calibrate intrinsics --insecure --auto --robot tcp://127.0.0.1:27970 "
                                     "--out " + (dir_ / "none.yaml").string(), dir_.string());
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("the robot never answered at tcp://127.0.0.1:27970"), std::string::npos) << r.err;
}

}  // namespace
