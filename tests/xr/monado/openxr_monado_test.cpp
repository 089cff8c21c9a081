// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr openxr` against a real OpenXR runtime: Monado from a Debian trixie root
///        (tests/xr/monado/build_trixie_root.sh), headless (null compositor, simulated HMD),
///        through run_with_monado.sh. Checks that the session reaches FOCUSED, that frames are
///        submitted, that the swapchain images equal the renderer's offscreen output for the eye
///        poses the app logged for each image (sRGB and linear swapchains), and that the app
///        exits by itself, cleanly, when the service stops. Skipped, saying why, when
///        TELESPHERE_MONADO_ROOT does not name a root.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "shaders/png_io.h"
#include "xr/openxr_test_scene.h"
#include "xr/spherical_renderer.h"

namespace telesphere::test {
namespace {

namespace fs = std::filesystem;

struct MonadoRun {
  int exit_code = -1;
  std::string output;
};

std::string monadoQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs `command` through sh with stdout and stderr captured; bounded by `timeout` (coreutils).
MonadoRun monadoRunCommand(const std::string& command, int timeout_s) {
  MonadoRun run;
  const std::string line = "timeout -k 5 " + std::to_string(timeout_s) + " " + command + " 2>&1";
  FILE* pipe = popen(line.c_str(), "r");
  if (!pipe) return run;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

std::string monadoRoot() {
  const char* root = std::getenv("TELESPHERE_MONADO_ROOT");
  return root ? root : "";
}

#define SKIP_WITHOUT_MONADO_ROOT()                                                              \
  do {                                                                                          \
    const std::string r = monadoRoot();                                                         \
    if (r.empty())                                                                              \
      GTEST_SKIP() << "TELESPHERE_MONADO_ROOT is not set: build a Monado root with "            \
                      "tests/xr/monado/build_trixie_root.sh DIR and set TELESPHERE_MONADO_ROOT=DIR"; \
    if (!fs::exists(fs::path(r) / "usr/bin/monado-service"))                                    \
      GTEST_SKIP() << "TELESPHERE_MONADO_ROOT=" << r                                            \
                   << " holds no Monado root (make one with tests/xr/monado/build_trixie_root.sh)"; \
  } while (0)

std::string monadoXrCommand(const std::string& wrapper_options, const std::string& app_options) {
  return monadoQuote(std::string(TELESPHERE_SOURCE_DIR) + "/tests/xr/monado/run_with_monado.sh") +
         " " + wrapper_options + " " + monadoQuote(monadoRoot()) + " -- " +
         monadoQuote(std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-xr") + " openxr " +
         app_options;
}

/// A number after `key` in `text` ("submitted 20"), or -1.
long long monadoNumberAfter(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return -1;
  return std::atoll(text.c_str() + at + key.size());
}

struct LoggedEye {
  long long frame = 0;
  int eye = 0;
  xr::EyeView view;
  bool srgb = true;
  std::string png;
};

std::vector<LoggedEye> monadoReadPoses(const std::string& path) {
  std::vector<LoggedEye> out;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) f.push_back(cell);
    if (f.size() != 18) continue;
    LoggedEye e;
    e.frame = std::stoll(f[0]);
    e.eye = std::stoi(f[1]);
    const Eigen::Quaterniond q(std::stod(f[9]), std::stod(f[6]), std::stod(f[7]), std::stod(f[8]));
    e.view.T_cam_eye = Eigen::Isometry3d::Identity();
    e.view.T_cam_eye.linear() = q.normalized().toRotationMatrix();
    e.view.T_cam_eye.translation() << std::stod(f[3]), std::stod(f[4]), std::stod(f[5]);
    e.view.fov = {std::stod(f[10]), std::stod(f[11]), std::stod(f[12]), std::stod(f[13])};
    e.view.width = std::stoi(f[14]);
    e.view.height = std::stoi(f[15]);
    e.srgb = f[16] == "1";
    e.png = f[17];
    out.push_back(e);
  }
  return out;
}

double monadoSrgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

struct ImageDifference {
  int max = 0;
  double mean = 0;
  double fraction_over_8 = 0;  ///< share of channel values more than 8 apart
};

/// Renders each logged eye offscreen (same scene, settings, poses) and compares with its PNG.
/// `linear`: the swapchain stores linear values, so the reference is sRGB-decoded first.
ImageDifference monadoCompare(const std::string& dir, const std::vector<LoggedEye>& eyes, bool linear) {
  ImageDifference d;
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  EXPECT_TRUE(context) << error;
  if (!context) return {255, 255, 1};
  xr::GpuCamera camera(xr::OpenXrTestScene::camera(), xr::OpenXrTestScene::kImageWidth,
                       xr::OpenXrTestScene::kImageHeight);
  EXPECT_TRUE(camera.upload(xr::OpenXrTestScene::image(), &error)) << error;
  xr::SphericalRenderer renderer;
  const xr::RenderSettings settings;  // the command's defaults: full6d, exact, r = 1 m
  double sum = 0;
  std::size_t count = 0, over = 0;
  for (const LoggedEye& e : eyes) {
    const auto png = gl::readPng(dir + "/" + e.png, &error);
    EXPECT_TRUE(png) << error;
    if (!png) return {255, 255, 1};
    EXPECT_EQ(png->width, e.view.width);
    EXPECT_EQ(png->height, e.view.height);
    gl::OffscreenTarget target(e.view.width, e.view.height, GL_RGBA8);
    EXPECT_TRUE(renderer.render(camera, e.view, settings, target.framebuffer(), &error)) << error;
    const auto reference = target.readRgba8();
    for (std::size_t i = 0; i < reference.size() && i < png->rgba.size(); ++i) {
      if (i % 4 == 3) continue;  // alpha
      int expected = reference[i];
      if (linear) expected = int(std::lround(255.0 * monadoSrgbToLinear(reference[i] / 255.0)));
      const int diff = std::abs(int(png->rgba[i]) - expected);
      d.max = std::max(d.max, diff);
      sum += diff;
      over += diff > 8 ? 1 : 0;
      ++count;
    }
  }
  d.mean = count ? sum / double(count) : 255.0;
  d.fraction_over_8 = count ? double(over) / double(count) : 1.0;
  return d;
}

fs::path monadoScratch(const std::string& name) {
  const fs::path dir = fs::path(TELESPHERE_BINARY_DIR) / "tests" / "openxr_monado" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void monadoExpectFocusedAndMatching(const std::string& colour, bool linear) {
  const fs::path dir = monadoScratch(colour);
  const int frames = 12;
  const MonadoRun run = monadoRunCommand(
      monadoXrCommand("", "--frames " + std::to_string(frames) + " --swapchain-colour " + colour +
                              " --readback-dir " + monadoQuote(dir.string())),
      240);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("focused: yes"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("FOCUSED"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("binding: XR_MNDX_egl_enable"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("AddressSanitizer"), std::string::npos) << run.output;
  const long long submitted = monadoNumberAfter(run.output, "submitted ");
  EXPECT_GE(submitted, frames) << run.output;
  EXPECT_LE(submitted, monadoNumberAfter(run.output, "waited ")) << run.output;
  const bool srgb_swapchain = run.output.find("swapchain: GL_SRGB8") != std::string::npos;
  EXPECT_EQ(srgb_swapchain, !linear) << "Monado offers both kinds; " << run.output;

  const auto eyes = monadoReadPoses((dir / "poses.csv").string());
  ASSERT_EQ(eyes.size(), std::size_t(2 * submitted)) << "one logged pose per eye and frame";
  for (const LoggedEye& e : eyes) ASSERT_EQ(e.srgb, !linear);
  // The simulated head moves: the logged poses differ between the first and last frames, and
  // each image is compared with the render for its own pose.
  EXPECT_GT((eyes.front().view.T_cam_eye.linear() - eyes.back().view.T_cam_eye.linear()).norm() +
                (eyes.front().view.T_cam_eye.translation() - eyes.back().view.T_cam_eye.translation()).norm(),
            0.0);
  const std::vector<LoggedEye> sample{eyes[0], eyes[1], eyes[eyes.size() / 2], eyes[eyes.size() - 1]};
  const ImageDifference d = monadoCompare(dir.string(), sample, linear);
  std::cout << "swapchain (" << colour << ") vs offscreen: max " << d.max << ", mean " << d.mean
            << ", share > 8: " << d.fraction_over_8 << "\n";
  EXPECT_LT(d.mean, linear ? 1.0 : 0.5);
  EXPECT_LT(d.fraction_over_8, 0.002);
}

TEST(OpenXrMonado, SrgbSwapchainReachesFocusedAndShowsTheOffscreenRender) {
  SKIP_WITHOUT_MONADO_ROOT();
  monadoExpectFocusedAndMatching("srgb", false);
}

TEST(OpenXrMonado, LinearSwapchainHoldsTheDecodedColours) {
  SKIP_WITHOUT_MONADO_ROOT();
  monadoExpectFocusedAndMatching("linear", true);
}

TEST(OpenXrMonado, AppExitsCleanlyWhenTheServiceStops) {
  SKIP_WITHOUT_MONADO_ROOT();
  // No --frames: the app would run until Ctrl-C; the service goes away under it.
  const MonadoRun run = monadoRunCommand(monadoXrCommand("--stop-service-after 8", ""), 120);
  EXPECT_EQ(run.exit_code, 4) << "4 = the runtime went away during the session\n" << run.output;
  EXPECT_NE(run.output.find("the OpenXR runtime went away"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("focused: yes"), std::string::npos) << "it was running first\n" << run.output;
  EXPECT_EQ(run.output.find("AddressSanitizer"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("runtime error:"), std::string::npos) << run.output;
}

TEST(OpenXrMonado, SigintEndsTheSessionCleanly) {
  SKIP_WITHOUT_MONADO_ROOT();
  // The wrapper forwards SIGINT to the app; `timeout -s INT` sends it after 8 s (and, with
  // --preserve-status, exits with the wrapper's status, i.e. the app's).
  const std::string command = "timeout --preserve-status -s INT 8 " + monadoXrCommand("", "");
  const MonadoRun run = monadoRunCommand(command, 120);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("interrupted: ending the session"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("STOPPING"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("AddressSanitizer"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace telesphere::test
