// SPDX-License-Identifier: MIT
/// @brief telesphere-calib's calibration tools end to end, as users run them: `intrinsics` on a
///        folder of rendered Aprilgrid PNGs (parameters in the output file against the truth,
///        progress lines, the degeneracy warning), its errors (unreadable image, too few views,
///        target never seen, missing folder or target, empty folder), `handeye` on a sample file
///        (with T_robot_flange, and with xArm 6 joint angles where the robot library is built)
///        and `report` with its coverage picture.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "calib/calibration_file.h"
#include "calib/target_detection.h"
#include "calib/target_render.h"
#include "calib/synthetic/calibration_sessions.h"
#ifdef TELESPHERE_CALIB_HAS_ROBOT
#include "robot/arm/xarm6_kinematics.h"
#endif

namespace telesphere::test {
namespace {

namespace fs = std::filesystem;
using namespace calib::synthetic;  // the simulated lenses, boards and sessions

const std::string kCalibTool = std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-calib";

struct ToolRun {
  int status;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

std::string readAll(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

ToolRun runTool(const fs::path& dir, const std::string& args) {
  const fs::path out = dir / "tool_stdout.txt", err = dir / "tool_stderr.txt";
  const int status =
      std::system((kCalibTool + " " + args + " > " + out.string() + " 2> " + err.string() + " < /dev/null").c_str());
  return {WEXITSTATUS(status), readAll(out), readAll(err)};
}

/// Renders views of the Aprilgrid through the 1280×1024 ds lens into `dir` as PNGs.
void renderViews(const fs::path& dir, const std::vector<Eigen::Isometry3d>& poses, std::uint32_t seed) {
  fs::create_directories(dir);
  const auto cam = lens1280();
  calib::RenderOptions ro;
  ro.supersampling = 2;
  ro.noise_sigma = 2.0;
  for (std::size_t v = 0; v < poses.size(); ++v) {
    ro.noise_seed = seed + static_cast<std::uint32_t>(v);
    const auto image = calib::renderTarget(cam.camera, cam.width, cam.height, poses[v],
                                           calib::aprilGridTexture(testGrid()), ro);
    char name[32];
    std::snprintf(name, sizeof name, "view_%03zu.png", v);
    ASSERT_TRUE(calib::writeGrayImage(image, (dir / name).string()));
  }
}

/// Images of the fixture, rendered once for all tests of the suite.
class CalibToolsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("telesphere_calib_tools_" + std::to_string(::getpid()));
    fs::create_directories(root_);
    std::ofstream(root_ / "aprilgrid.yaml")
        << "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\ntagSize: 0.088\ntagSpacing: 0.3\n";
    std::mt19937 rng(41);
    renderViews(root_ / "good", spreadBoardPoses(lens1280(), testGrid(), 14, 95.0 * M_PI / 180, rng), 100);
    renderViews(root_ / "degenerate", frontoParallelCentreBoardPoses(testGrid(), 8, rng), 200);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  static std::string target() { return (root_ / "aprilgrid.yaml").string(); }

  static fs::path root_;
};

fs::path CalibToolsCli::root_;

TEST_F(CalibToolsCli, IntrinsicsFromRenderedImagesWritesTheCalibrationAndReport) {
  const fs::path out = root_ / "good.yaml";
  const ToolRun r = runTool(root_, "intrinsics --images " + (root_ / "good").string() + " --target " + target() +
                                       " --model ds --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  // Progress during detection and optimisation.
  EXPECT_NE(r.err.find("detecting cam_l 1/14 view_000.png:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("detecting cam_l 14/14 view_013.png:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cam_l intrinsics: iteration 1,"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("WARNING"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("reprojection error: RMS"), std::string::npos) << r.out;
  const auto calib = calib::loadCalibrationFile(out.string());
  ASSERT_TRUE(calib) << calib.error().describe();
  ASSERT_EQ(calib->cameras.size(), 1u);
  EXPECT_EQ(calib->cameras[0].width, 1280);
  EXPECT_EQ(calib->cameras[0].height, 1024);
  const Eigen::VectorXd p = calib->cameras[0].camera.params(), truth = lens1280().camera.params();
  EXPECT_NEAR(p[0] / truth[0], 1.0, 5e-3) << p.transpose();
  EXPECT_NEAR(p[1] / truth[1], 1.0, 5e-3) << p.transpose();
  EXPECT_NEAR(p[2], truth[2], 1.0) << p.transpose();
  EXPECT_NEAR(p[3], truth[3], 1.0) << p.transpose();
  EXPECT_NEAR(p[4], truth[4], 0.02) << p.transpose();
  EXPECT_NEAR(p[5], truth[5], 0.02) << p.transpose();

  // `report` reads the report written beside the calibration and draws the coverage picture.
  const ToolRun rep = runTool(root_, "report --report " + out.string() + ".report.json --coverage " +
                                         (root_ / "coverage").string());
  ASSERT_EQ(rep.status, 0) << rep.err;
  EXPECT_NE(rep.out.find("camera model: ds, resolution 1280x1024"), std::string::npos) << rep.out;
  EXPECT_NE(rep.out.find("separability: focal length vs distortion"), std::string::npos) << rep.out;
  EXPECT_EQ(rep.out.find("WARNING"), std::string::npos) << rep.out;
  const auto picture = calib::readGrayImage((root_ / "coverage_cam_l.png").string());
  ASSERT_TRUE(picture);
  EXPECT_EQ(picture->width, 640);
  EXPECT_EQ(picture->height, 512);
}

TEST_F(CalibToolsCli, IntrinsicsWarnsWhenTheViewsAreDegenerate) {
  const fs::path out = root_ / "degenerate.yaml";
  const ToolRun r = runTool(root_, "intrinsics --images " + (root_ / "degenerate").string() + " --target " +
                                       target() + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("telesphere-calib: WARNING: cam_l: the views do not separate the focal length from xi, alpha"),
            std::string::npos)
      << r.err;
  const ToolRun rep = runTool(root_, "report --report " + out.string() + ".report.json");
  ASSERT_EQ(rep.status, 0) << rep.err;
  EXPECT_NE(rep.out.find("WARNING: cam_l: the views do not separate"), std::string::npos) << rep.out;
}

TEST_F(CalibToolsCli, IntrinsicsErrorsAreClear) {
  const fs::path dir = root_ / "errors";
  // An unreadable image among good ones.
  fs::create_directories(dir / "unreadable");
  fs::copy_file(root_ / "good" / "view_000.png", dir / "unreadable" / "a.png");
  std::ofstream(dir / "unreadable" / "b.png") << "this is not a PNG";
  ToolRun r = runTool(dir, "intrinsics --images " + (dir / "unreadable").string() + " --target " + target() +
                               " --out " + (dir / "x.yaml").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot read the image " + (dir / "unreadable" / "b.png").string()), std::string::npos)
      << r.err;
  // Too few views: two images.
  fs::create_directories(dir / "two");
  for (const char* name : {"view_000.png", "view_001.png"}) fs::copy_file(root_ / "good" / name, dir / "two" / name);
  r = runTool(dir, "intrinsics --images " + (dir / "two").string() + " --target " + target() + " --out " +
                       (dir / "x.yaml").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("usable views, at least 3 needed"), std::string::npos) << r.err;
  // The target is never seen: blank images.
  fs::create_directories(dir / "blank");
  calib::GrayImage blank(320, 240);
  std::fill(blank.pixels.begin(), blank.pixels.end(), std::uint8_t{128});
  for (const char* name : {"0.png", "1.png", "2.png", "3.png"})
    ASSERT_TRUE(calib::writeGrayImage(blank, (dir / "blank" / name).string()));
  r = runTool(dir, "intrinsics --images " + (dir / "blank").string() + " --target " + target() + " --out " +
                       (dir / "x.yaml").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cam_l: the target was never seen"), std::string::npos) << r.err;
  // Missing folder, missing target file, a folder without images.
  r = runTool(dir, "intrinsics --images " + (dir / "nowhere").string() + " --target " + target() + " --out " +
                       (dir / "x.yaml").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find((dir / "nowhere").string()), std::string::npos) << r.err;
  r = runTool(dir, "intrinsics --images " + (dir / "two").string() + " --target " + (dir / "no.yaml").string() +
                       " --out " + (dir / "x.yaml").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find((dir / "no.yaml").string()), std::string::npos) << r.err;
  fs::create_directories(dir / "empty");
  r = runTool(dir, "intrinsics --images " + (dir / "empty").string() + " --target " + target() + " --out " +
                       (dir / "x.yaml").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no images in " + (dir / "empty").string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.yaml"));
}

/// A pose as the sample file writes it.
std::string poseYaml(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  char buf[256];
  std::snprintf(buf, sizeof buf, "{translation: [%.17g, %.17g, %.17g], rotation_xyzw: [%.17g, %.17g, %.17g, %.17g]}",
                T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w());
  return buf;
}

std::string cornersYaml(const std::array<Eigen::Vector2d, 4>& c) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "[[%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g]]", c[0].x(),
                c[0].y(), c[1].x(), c[1].y(), c[2].x(), c[2].y(), c[3].x(), c[3].y());
  return buf;
}

/// Writes the stereo head's intrinsics (the truth) to `path`.
void writeStereoIntrinsics(const fs::path& path) {
  calib::SystemCalibration system;
  system.cameras.push_back({"cam_l", lens1280(false).camera, 1280, 1024});
  system.cameras.push_back({"cam_r", lens1280(true).camera, 1280, 1024});
  system.T_cam_l_cam_r = trueTCamLCamR();
  ASSERT_FALSE(calib::saveCalibrationFile(system, path.string(), calib::CalibrationFormat::kTelesphere));
}

void expectHandEyeRecovered(const fs::path& out_path, const HandEyeTruth& truth) {
  const auto out = calib::loadCalibrationFile(out_path.string());
  ASSERT_TRUE(out) << out.error().describe();
  ASSERT_TRUE(out->T_flange_cam_l && out->T_robot_mount && out->T_wrist_marker);
  EXPECT_LT(translationError(*out->T_flange_cam_l, truth.T_flange_cam_l), 2e-3);
  EXPECT_LT(rotationErrorDeg(*out->T_flange_cam_l, truth.T_flange_cam_l), 0.2);
  EXPECT_LT(translationError(*out->T_robot_mount, truth.T_robot_mount), 2e-3);
  EXPECT_LT(translationError(*out->T_wrist_marker, truth.T_wrist_marker), 2e-3);
  EXPECT_EQ(out->cameras.size(), 2u);  // the intrinsics pass through
}

TEST_F(CalibToolsCli, HandEyeFromASampleFile) {
  const fs::path dir = root_ / "handeye";
  fs::create_directories(dir);
  writeStereoIntrinsics(dir / "intrinsics.yaml");
  const HandEyeTruth truth = handEyeTruth();
  const auto samples = simulateHandEyeSession(truth, lens1280(false), lens1280(true), trueTCamLCamR(), 0.1, 40,
                                              0.3, 17);
  ASSERT_EQ(samples.size(), 40u);
  {
    std::ofstream f(dir / "samples.yaml");
    f << "marker: {dictionary: DICT_4X4_50, id: 0, size: 0.1}\nsamples:\n";
    for (const auto& s : samples)
      f << "  - t_ns: " << s.t_ns << "\n    T_robot_flange: " << poseYaml(s.T_robot_flange)
        << "\n    T_mount_wrist: " << poseYaml(s.T_mount_wrist) << "\n    corners_l: " << cornersYaml(*s.corners_l)
        << "\n    corners_r: " << cornersYaml(*s.corners_r) << "\n";
  }
  const ToolRun r = runTool(dir, "handeye --samples " + (dir / "samples.yaml").string() + " --calib " +
                                     (dir / "intrinsics.yaml").string() + " --out " + (dir / "out.yaml").string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("hand-eye: 40 samples"), std::string::npos) << r.out;
  expectHandEyeRecovered(dir / "out.yaml", truth);

  // Too few samples: a clear error, no output file.
  {
    std::ofstream f(dir / "few.yaml");
    f << "marker: {dictionary: DICT_4X4_50, id: 0, size: 0.1}\nsamples:\n";
    for (std::size_t i = 0; i < 3; ++i)
      f << "  - T_robot_flange: " << poseYaml(samples[i].T_robot_flange)
        << "\n    T_mount_wrist: " << poseYaml(samples[i].T_mount_wrist)
        << "\n    corners_l: " << cornersYaml(*samples[i].corners_l) << "\n";
  }
  const ToolRun few = runTool(dir, "handeye --samples " + (dir / "few.yaml").string() + " --calib " +
                                       (dir / "intrinsics.yaml").string() + " --out " + (dir / "few_out.yaml").string());
  EXPECT_EQ(few.status, 2) << few.err;
  EXPECT_NE(few.err.find("telesphere-calib: "), std::string::npos) << few.err;
  EXPECT_FALSE(fs::exists(dir / "few_out.yaml"));
}

TEST_F(CalibToolsCli, HandEyeFromHeadArmJointAngles) {
#ifndef TELESPHERE_CALIB_HAS_ROBOT
  GTEST_SKIP() << "telesphere::robot (xArm 6 kinematics) is not part of this build";
#else
  const fs::path dir = root_ / "handeye_joints";
  fs::create_directories(dir);
  writeStereoIntrinsics(dir / "intrinsics.yaml");
  const HandEyeTruth truth = handEyeTruth();
  const robot::arm::Xarm6Kinematics arm;
  // Head motion in joint space: J1 (yaw), J5 and J4 (pitch, roll of the wrist) about a working pose.
  const auto q_at = [](int i) {
    const double phase = 0.37 * i;
    robot::arm::JointVector q;
    q << 0.6 * std::sin(phase), -0.3, -0.8, 0.25 * std::sin(0.7 * phase), 1.1 + 0.35 * std::sin(1.3 * phase), 0.0;
    return q;
  };
  int last_attempt = -1;
  const auto samples =
      simulateHandEyeSession(truth, lens1280(false), lens1280(true), trueTCamLCamR(), 0.1, 40, 0.3, 23, true,
                             [&](int i) {
                               last_attempt = i;
                               return arm.forward(q_at(i));
                             });
  ASSERT_EQ(samples.size(), 40u);
  {
    std::ofstream f(dir / "samples.yaml");
    f << "marker: {dictionary: DICT_4X4_50, id: 0, size: 0.1}\nsamples:\n";
    for (const auto& s : samples) {
      // t_ns = attempt · 100 ms (see simulateHandEyeSession): the attempt gives the joint angles.
      const robot::arm::JointVector q = q_at(static_cast<int>(s.t_ns / 100000000));
      char buf[256];
      std::snprintf(buf, sizeof buf, "[%.17g, %.17g, %.17g, %.17g, %.17g, %.17g]", q[0], q[1], q[2], q[3], q[4], q[5]);
      f << "  - t_ns: " << s.t_ns << "\n    q_head: " << buf << "\n    T_mount_wrist: " << poseYaml(s.T_mount_wrist)
        << "\n    corners_l: " << cornersYaml(*s.corners_l) << "\n    corners_r: " << cornersYaml(*s.corners_r)
        << "\n";
    }
  }
  EXPECT_GE(last_attempt, 39);
  const ToolRun r = runTool(dir, "handeye --samples " + (dir / "samples.yaml").string() + " --calib " +
                                     (dir / "intrinsics.yaml").string() + " --out " + (dir / "out.yaml").string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  expectHandEyeRecovered(dir / "out.yaml", truth);

  // Five angles for a six-joint arm: the error names the sample and the field.
  std::ofstream(dir / "bad.yaml") << "marker: {dictionary: DICT_4X4_50, id: 0, size: 0.1}\nsamples:\n"
                                     "  - q_head: [0, 0, 0, 0, 0]\n    T_mount_wrist: "
                                  << poseYaml(Eigen::Isometry3d::Identity()) << "\n";
  const ToolRun bad = runTool(dir, "handeye --samples " + (dir / "bad.yaml").string() + " --calib " +
                                       (dir / "intrinsics.yaml").string() + " --out " + (dir / "bad_out.yaml").string());
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("samples[0].q_head: expected 6 xArm 6 joint angles (rad), got 5"), std::string::npos)
      << bad.err;
#endif
}

}  // namespace
}  // namespace telesphere::test
