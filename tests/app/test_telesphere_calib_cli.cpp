// SPDX-License-Identifier: MIT
/// @brief telesphere-calib as users run it: `model project|unproject` on stdin with every input
///        format, full double precision, `invalid` lines, errors; `convert` and `info`.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "calib/calibration_file.h"

namespace telesphere::test {
namespace {

const std::string kTool = std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-calib";
const std::string kSim = std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml";

struct CliResult {
  int status;
  std::string out;
};

/// Runs `args` with `input` on stdin; stdout captured, stderr into out after "STDERR:".
CliResult run(const std::string& args, const std::string& input) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string in_path = (dir / "telesphere_cli_in.txt").string();
  const std::string err_path = (dir / "telesphere_cli_err.txt").string();
  std::ofstream(in_path) << input;
  FILE* pipe = popen((kTool + " " + args + " < " + in_path + " 2> " + err_path).c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  std::ifstream err(err_path);
  std::stringstream e;
  e << err.rdbuf();
  if (!e.str().empty()) out += "STDERR:" + e.str();
  return {WEXITSTATUS(status), out};
}

TEST(TelesphereCalibCli, ProjectsAndUnprojectsWithFullPrecision) {
  const auto calib = calib::loadCalibrationFile(kSim);
  ASSERT_TRUE(calib) << calib.error().describe();
  const CliResult r = run("model project --calib " + kSim + " --camera 1",
                    "0 0 1\n# a comment\n\n0.3 -0.2 1.5\n0 0 -1\n1 2\n0 0 0\n");
  EXPECT_EQ(r.status, 3) << r.out;  // one malformed line
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "1919.5 1079.5");
  std::getline(lines, line);
  EXPECT_EQ(line, "# a comment");
  std::getline(lines, line);
  EXPECT_EQ(line, "");
  std::getline(lines, line);
  double u, v;
  ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf", &u, &v), 2) << line;
  Eigen::Vector2d expected;
  ASSERT_TRUE(calib->cameras[1].camera.project(Eigen::Vector3d(0.3, -0.2, 1.5), expected));
  EXPECT_EQ(u, expected.x());  // bit-exact through %.17g
  EXPECT_EQ(v, expected.y());
  std::getline(lines, line);
  EXPECT_EQ(line, "invalid");  // straight behind the camera
  std::getline(lines, line);
  EXPECT_EQ(line, "invalid");  // malformed
  std::getline(lines, line);
  EXPECT_EQ(line, "invalid");  // the camera centre
  EXPECT_NE(r.out.find("stdin line 6: expected 3 numbers"), std::string::npos) << r.out;
}

TEST(TelesphereCalibCli, UnprojectReadsEveryFormat) {
  const auto dir = std::filesystem::temp_directory_path() / "telesphere_cli_formats";
  std::filesystem::create_directories(dir);
  for (const char* format : {"telesphere", "kalibr", "basalt"}) {
    const std::string path = (dir / (std::string(format) + ".calib")).string();
    const CliResult c = run("convert --calib " + kSim + " --out " + path + " --format " + format, "");
    ASSERT_EQ(c.status, 0) << c.out;
    const CliResult r = run("model unproject --calib " + path, "1919.5 1079.5\n0 0\n-5000 0\n");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(r.out, "0 0 1\ninvalid\ninvalid\n") << format;
  }
  std::filesystem::remove_all(dir);
}

TEST(TelesphereCalibCli, ClearErrors) {
  const CliResult missing_camera = run("model project --calib " + kSim + " --camera 2", "");
  EXPECT_EQ(missing_camera.status, 2);
  EXPECT_NE(missing_camera.out.find("--camera 2 does not exist"), std::string::npos) << missing_camera.out;
  const auto bad = std::filesystem::temp_directory_path() / "telesphere_cli_bad.yaml";
  std::ofstream(bad) << "version: 1\ncameras:\n  - label: cam_l\n    model: ds\n    resolution: [640, 480]\n"
                        "    intrinsics: {fx: 300, fy: 300, cx: 320, cy: 240, xi: 0, alpha: 2}\n";
  const CliResult r = run("model project --calib " + bad.string(), "");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("telesphere_cli_bad.yaml:6: cameras[0].intrinsics.alpha: alpha = 2 is outside [0, 1]"),
            std::string::npos)
      << r.out;
  std::filesystem::remove(bad);
}

TEST(TelesphereCalibCli, InfoShowsTheFieldOfView) {
  const CliResult r = run("info --calib " + kSim, "");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("cam_l: ds 3840x2160"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("image horizontal field of view 19"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("T_robot_mount: not calibrated"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace telesphere::test
