// SPDX-License-Identifier: MIT
/// @brief End-to-end test of `telesphere-xr still`: a calibration file and a camera image on disk,
///        the command run as users run it, its PNG compared with the reference renderer; bad
///        input (NaN pose, wrong image size, malformed options) exits non-zero without output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "shaders/png_io.h"
#include "tests/xr/render_fixtures.h"
#include "xr/render/reference_renderer.h"

namespace telesphere::xr {
namespace {

namespace fs = std::filesystem;

class StillCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("telesphere_still_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // A double-sphere camera like the paper's, scaled to 960×540.
    std::ofstream(dir_ / "calib.yaml")
        << "version: 1\ncameras:\n  - label: cam_l\n    model: ds\n    resolution: [960, 540]\n"
           "    intrinsics: {fx: 232.5, fy: 232.5, cx: 479.5, cy: 269.5, xi: -0.18, alpha: 0.59}\n";
    picture_.resize(960u * 540u * 4u);
    for (int y = 0; y < 540; ++y)
      for (int x = 0; x < 960; ++x) {
        std::uint8_t* p = &picture_[(y * 960u + x) * 4u];
        p[0] = std::uint8_t(x * 255 / 959);
        p[1] = std::uint8_t(y * 255 / 539);
        p[2] = ((x / 30 + y / 30) % 2) ? 200 : 40;
        p[3] = 255;
      }
    ASSERT_TRUE(gl::writePng((dir_ / "cam.png").string(), 960, 540, 4, picture_.data()));
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs the command with `args` appended; returns its exit status.
  int run(const std::string& args) const {
    const std::string command = std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-xr still --calib " +
                                (dir_ / "calib.yaml").string() + " --image " +
                                (dir_ / "cam.png").string() + " " + args + " 2>" +
                                (dir_ / "stderr.txt").string();
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::string stderrText() const {
    std::ifstream in(dir_ / "stderr.txt");
    return {std::istreambuf_iterator<char>(in), {}};
  }

  fs::path dir_;
  std::vector<std::uint8_t> picture_;
};

TEST_F(StillCommand, RendersWhatTheReferenceRenders) {
  const std::string out = (dir_ / "eye.png").string();
  // Eye 3 cm right of the camera, turned 20° to the left (about the camera's y axis), looking
  // along the optical axis otherwise: R_cam_eye = R_y(−20°)·diag(1, −1, −1).
  const Eigen::Isometry3d T_cam_eye = test::eyePose({0.03, 0, 0}, test::rotation(-0.349, {0, 1, 0}));
  const Eigen::Quaterniond q(T_cam_eye.linear());
  std::ostringstream pose;
  pose.precision(17);
  pose << "0.03 0 0 " << q.x() << " " << q.y() << " " << q.z() << " " << q.w();
  for (const char* path : {"exact", "mesh", "lut"}) {
    ASSERT_EQ(run("--camera 0 --T-cam-eye \"" + pose.str() +
                  "\" --fov \"-0.7 0.6 0.65 -0.6\" --size 120x100 --radius 1.5 --mode full6d "
                  "--path " + path + " --out " + out),
              0)
        << stderrText();
    std::string error;
    const auto png = gl::readPng(out, &error);
    ASSERT_TRUE(png) << error;
    ASSERT_EQ(png->width, 120);
    ASSERT_EQ(png->height, 100);

    render::EyeView view;
    view.fov = {-0.7, 0.6, 0.65, -0.6};
    view.width = 120;
    view.height = 100;
    view.T_cam_eye = T_cam_eye;
    render::RenderSettings s;
    s.radius = 1.5;
    std::vector<std::uint8_t> rgb;
    for (std::size_t i = 0; i < picture_.size(); ++i)
      if (i % 4 != 3) rgb.push_back(picture_[i]);
    const auto camera = calib::GenericCamera(calib::DoubleSphereCamera<double>(
        (Eigen::Matrix<double, 6, 1>() << 232.5, 232.5, 479.5, 269.5, -0.18, 0.59).finished()));
    const auto ref = render::renderReference(camera, render::SourceImage::rgb8(960, 540, rgb), view, s);
    ASSERT_TRUE(ref);
    int far_off = 0;
    for (std::size_t i = 0; i < png->rgba.size(); ++i)
      if (std::abs(png->rgba[i] / 255.0 - ref->rgba[i]) > 6.0 / 255.0) ++far_off;
    // Checker edges may differ by a fraction of a pixel on the mesh path.
    EXPECT_LE(far_off, std::string(path) == "mesh" ? 200 : 40) << path;
  }
}

TEST_F(StillCommand, RejectsBadInputWithoutWriting) {
  const std::string out = (dir_ / "never.png").string();
  const std::string good_fov = " --fov \"-0.7 0.6 0.65 -0.6\" --size 64x48 --out " + out;
  EXPECT_EQ(run("--T-cam-eye \"nan 0 0 1 0 0 0\"" + good_fov), 1);
  EXPECT_NE(stderrText().find("T_cam_eye"), std::string::npos) << stderrText();
  EXPECT_EQ(run("--T-cam-eye \"0 0 0 1 0 0\"" + good_fov), 1);
  EXPECT_EQ(run("--T-cam-eye \"0 0 0 2 0 0 0\"" + good_fov), 1);
  EXPECT_EQ(run("--camera 3 --T-cam-eye \"0 0 0 1 0 0 0\"" + good_fov), 1);
  EXPECT_EQ(run("--T-cam-eye \"0 0 0 1 0 0 0\" --mode 6d" + good_fov), 1);
  EXPECT_EQ(run("--T-cam-eye \"0 0 0 1 0 0 0\" --radius 0" + good_fov), 1);
  EXPECT_EQ(run("--T-cam-eye \"0 0 0 1 0 0 0\" --fov \"0.7 -0.6 0.65 -0.6\" --out " + out), 1);
  EXPECT_FALSE(fs::exists(out));
  // The calibration says 960×540; a 961×540 image is refused.
  std::vector<std::uint8_t> wrong(961u * 540u * 4u, 255);
  ASSERT_TRUE(gl::writePng((dir_ / "cam.png").string(), 961, 540, 4, wrong.data()));
  EXPECT_EQ(run("--T-cam-eye \"0 0 0 1 0 0 0\"" + good_fov), 1);
  EXPECT_NE(stderrText().find("960x540"), std::string::npos) << stderrText();
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace telesphere::xr
