// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr openxr` against a real OpenXR runtime: Monado from a Debian trixie root
///        (tests/xr/monado/build_trixie_root.sh), headless (null compositor, simulated HMD),
///        through run_with_monado.sh. Checks that the session reaches FOCUSED, that frames are
///        submitted, that the swapchain images equal the renderer's offscreen output for the eye
///        poses the app logged for each image (sRGB and linear swapchains), and that the app
///        exits by itself, cleanly, when the service stops. Skipped, saying why, when
///        TELESPHERE_MONADO_ROOT does not name a root.
///
///        Leaks: the app runs with LeakSanitizer reporting but not deciding the exit status
///        (exitcode=0), and each leak block is sorted by its allocating frame (leak_report.h): one
///        allocated in a library of the side root (Mesa, Monado, its loader) is not ours and only
///        counted; one allocated anywhere else, and every other sanitizer report, fails the test.
///        The root's package versions are printed first, so a failure names them.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "robot/link/link_client.h"
#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "shaders/png_io.h"
#include "tests/xr/monado/leak_report.h"
#include "xr/frame_loop/link_state_overlay.h"
#include "xr/openxr/openxr_test_scene.h"
#include "xr/render/spherical_renderer.h"
#include "xr/render/yuv_planes_file.h"

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
/// LeakSanitizer in the processes it starts reports but keeps their exit status (exitcode=0; this
/// also sets the status of other sanitizer errors, which monadoExpectNothingOfOurs finds by text).
MonadoRun monadoRunCommand(const std::string& command, int timeout_s) {
  MonadoRun run;
  const std::string line =
      "LSAN_OPTIONS=exitcode=0 timeout -k 5 " + std::to_string(timeout_s) + " " + command + " 2>&1";
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
  if (!root || !*root) return "";
  return fs::absolute(root).lexically_normal().string();
}

/// The side root's versions of the packages whose code runs in the app (build_trixie_root.sh
/// writes them), one line: what a failure here depends on besides our code.
std::string monadoRootVersions() {
  const std::string root = monadoRoot();
  std::ifstream in(fs::path(root) / "telesphere-monado-versions.txt");
  if (!in) return "side root " + root + ": no telesphere-monado-versions.txt";
  static const char* const kPackages[] = {"monado-service", "libopenxr1-monado", "libopenxr-loader1",
                                          "mesa-vulkan-drivers", "libgl1-mesa-dri", "libegl-mesa0",
                                          "libglx-mesa0", "libc6", "libstdc++6", "libvulkan1"};
  std::string versions = "side root " + root + ":";
  for (std::string line; std::getline(in, line);) {
    const std::string package = line.substr(0, line.find(' '));
    for (const char* wanted : kPackages)
      if (package == wanted) versions += " " + line + ";";
  }
  return versions;
}

/// Prints the side root's versions once, before the first test.
class MonadoVersionsEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    if (!monadoRoot().empty()) std::cout << monadoRootVersions() << "\n";
  }
};
const auto* const kMonadoVersions = ::testing::AddGlobalTestEnvironment(new MonadoVersionsEnvironment);

/// The sanitizers' findings in a run, leak blocks sorted by whose code allocated them.
SanitizerFindings monadoFindings(const MonadoRun& run) {
  std::vector<std::string> roots{monadoRoot()};
  std::error_code error;
  const fs::path canonical = fs::canonical(monadoRoot(), error);
  if (!error && canonical.string() != roots.front()) roots.push_back(canonical.string());
  return classifySanitizerOutput(run.output, roots);
}

/// No sanitizer report of ours in `run`: no leak allocated outside the side root, no other error.
/// The side root's own leaks are printed as a count.
void monadoExpectNothingOfOurs(const MonadoRun& run) {
  const SanitizerFindings findings = monadoFindings(run);
  if (!findings.foreign.empty()) std::cout << "not ours: " << findings.foreignSummary() << "\n";
  EXPECT_TRUE(findings.ours.empty() && findings.other_reports.empty())
      << "sanitizer reports of our code (" << monadoRootVersions() << ")\n"
      << findings.oursText() << "\n--- the whole output\n"
      << run.output;
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
         monadoQuote(std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-xr") + " openxr --insecure " +
         app_options;
}

/// A number after `key` in `text` ("submitted 20"), or -1.
long long monadoNumberAfter(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return -1;
  return std::atoll(text.c_str() + at + key.size());
}

struct LoggedEye {
  int session = 0;
  long long frame = 0;
  int eye = 0;
  xr::render::EyeView view;
  bool srgb = true;
  std::string png;
  unsigned long long sequence = 0;  ///< the robot's stereo frame shown (0: test scene / none)
  std::string mode;
  double radius = 0;
  /// The link's cues drawn over the eye (xr/frame_loop/link_state_overlay.h).
  float image_saturation = 1.0f;
  xr::frame_loop::LinkState link_state;
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
    if (f.size() == 25) f.emplace_back();  // an empty stream text at the line's end
    if (f.size() != 26) continue;
    LoggedEye e;
    e.session = std::stoi(f[0]);
    e.frame = std::stoll(f[1]);
    e.eye = std::stoi(f[2]);
    const Eigen::Quaterniond q(std::stod(f[10]), std::stod(f[7]), std::stod(f[8]), std::stod(f[9]));
    e.view.T_cam_eye = Eigen::Isometry3d::Identity();
    e.view.T_cam_eye.linear() = q.normalized().toRotationMatrix();
    e.view.T_cam_eye.translation() << std::stod(f[4]), std::stod(f[5]), std::stod(f[6]);
    e.view.fov = {std::stod(f[11]), std::stod(f[12]), std::stod(f[13]), std::stod(f[14])};
    e.view.width = std::stoi(f[15]);
    e.view.height = std::stoi(f[16]);
    e.srgb = f[17] == "1";
    e.png = f[18];
    e.sequence = std::stoull(f[19]);
    e.mode = f[20];
    e.radius = std::stod(f[21]);
    e.image_saturation = std::stof(f[22]);
    e.link_state.image_age_ms = std::stod(f[23]);
    e.link_state.eye_camera_distance_m = std::stod(f[24]);
    e.link_state.stream_text = f[25];
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
  xr::render::GpuCamera camera(xr::openxr::OpenXrTestScene::camera(), xr::openxr::OpenXrTestScene::kImageWidth,
                       xr::openxr::OpenXrTestScene::kImageHeight);
  EXPECT_TRUE(camera.upload(xr::openxr::OpenXrTestScene::image(), &error)) << error;
  xr::render::SphericalRenderer renderer;
  const xr::render::RenderSettings settings;  // the command's defaults: full6d, exact, r = 1 m
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

/// `binding` "egl" runs headless; "glx" runs on a private Xvfb (tests/xr/with_xvfb.sh) with the
/// Xlib binding and the mirror window.
void monadoExpectFocusedAndMatching(const std::string& colour, bool linear, const std::string& binding = "egl") {
  const fs::path dir = monadoScratch(colour + "-" + binding);
  const int frames = 12;
  std::string command =
      monadoXrCommand("", "--test-scene --frames " + std::to_string(frames) + " --swapchain-colour " + colour +
                              " --binding " + binding + (binding == "glx" ? " --mirror" : "") + " --readback-dir " +
                              monadoQuote(dir.string()) + " --out " + monadoQuote(dir.string()));
  if (binding == "glx")
    command = monadoQuote(std::string(TELESPHERE_SOURCE_DIR) + "/tests/xr/with_xvfb.sh") + " " + command;
  const MonadoRun run = monadoRunCommand(command, 240);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("focused: yes"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("FOCUSED"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(binding == "glx" ? "binding: XR_KHR_opengl_enable (Xlib/GLX)" : "binding: XR_MNDX_egl_enable"),
            std::string::npos)
      << run.output;
  monadoExpectNothingOfOurs(run);
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
  if (binding == "glx") {
    // The mirror window showed both eyes: each half of its last picture has the scene's colours
    // (not only the letterbox black).
    std::string error;
    const auto mirror = gl::readPng((dir / "mirror_last.png").string(), &error);
    ASSERT_TRUE(mirror) << error;
    for (int half = 0; half < 2; ++half) {
      std::size_t lit = 0;
      for (int y = 0; y < mirror->height; ++y)
        for (int x = half * mirror->width / 2; x < (half + 1) * mirror->width / 2; ++x) {
          const std::uint8_t* p = &mirror->rgba[(std::size_t(y) * std::size_t(mirror->width) + std::size_t(x)) * 4];
          lit += (p[0] > 40 || p[1] > 40 || p[2] > 40) ? 1 : 0;
        }
      EXPECT_GT(lit, std::size_t(mirror->width) * std::size_t(mirror->height) / 8) << "mirror half " << half;
    }
  }
}

TEST(OpenXrMonado, SrgbSwapchainReachesFocusedAndShowsTheOffscreenRender) {
  SKIP_WITHOUT_MONADO_ROOT();
  monadoExpectFocusedAndMatching("srgb", false);
}

TEST(OpenXrMonado, GlxBindingWithMirrorWindowShowsTheOffscreenRender) {
  SKIP_WITHOUT_MONADO_ROOT();
  monadoExpectFocusedAndMatching("srgb", false, "glx");
}

TEST(OpenXrMonado, LinearSwapchainHoldsTheDecodedColours) {
  SKIP_WITHOUT_MONADO_ROOT();
  monadoExpectFocusedAndMatching("linear", true);
}

TEST(OpenXrMonado, AppExitsCleanlyWhenTheServiceStops) {
  SKIP_WITHOUT_MONADO_ROOT();
  // No --frames: the app would run until Ctrl-C; the service goes away under it.
  const MonadoRun run = monadoRunCommand(monadoXrCommand("--stop-service-after 8", "--test-scene --reconnect 0"), 120);
  EXPECT_EQ(run.exit_code, 4) << "4 = the runtime went away during the session\n" << run.output;
  EXPECT_NE(run.output.find("the OpenXR runtime went away"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("focused: yes"), std::string::npos) << "it was running first\n" << run.output;
  monadoExpectNothingOfOurs(run);
}

TEST(OpenXrMonado, SigintEndsTheSessionCleanly) {
  SKIP_WITHOUT_MONADO_ROOT();
  // The wrapper forwards SIGINT to the app; `timeout -s INT` sends it after 8 s (and, with
  // --preserve-status, exits with the wrapper's status, i.e. the app's).
  const std::string command = "timeout --preserve-status -s INT 8 " + monadoXrCommand("", "--test-scene");
  const MonadoRun run = monadoRunCommand(command, 120);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("interrupted: ending the session"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("STOPPING"), std::string::npos) << run.output;
  monadoExpectNothingOfOurs(run);
}

TEST(OpenXrMonado, ReconnectsWhenTheRuntimeRestarts) {
  SKIP_WITHOUT_MONADO_ROOT();
  // The service stops 7 s in and starts again 2 s later; the app waits for it (--reconnect),
  // starts a second session, and ends both cleanly on Ctrl-C.
  const std::string command = "timeout --preserve-status -s INT 25 " +
                              monadoXrCommand("--restart-service-after 7", "--test-scene --reconnect 30");
  const MonadoRun run = monadoRunCommand(command, 150);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("waiting up to 30 s for it to come back"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("session 2: runtime: Monado"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("sessions: 2"), std::string::npos) << run.output;
  const auto second = run.output.find(" | ", run.output.find("states: "));
  ASSERT_NE(second, std::string::npos) << "two sessions' states\n" << run.output;
  EXPECT_NE(run.output.find("FOCUSED", second), std::string::npos) << "the second session ran\n" << run.output;
  monadoExpectNothingOfOurs(run);
}

#ifdef __SANITIZE_ADDRESS__
/// The mapped file of the running process whose name contains `name` ("libasan.so"), or "". Only
/// the sanitizer build's test uses it (an unused function warns in the Release tree).
std::string monadoMappedLibrary(const std::string& name) {
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.find('/');
    if (slash != std::string::npos && line.find(name, slash) != std::string::npos) return line.substr(slash);
  }
  return "";
}
#endif

TEST(OpenXrMonado, DeliberateLeakOfOursIsStillReported) {
  SKIP_WITHOUT_MONADO_ROOT();
#ifndef __SANITIZE_ADDRESS__
  GTEST_SKIP() << "not a sanitizer build (-DTELESPHERE_SANITIZE=ON): the app has no LeakSanitizer";
#else
  // Our library, preloaded into the app behind the sanitizer runtime (which must come first),
  // leaks 4321 bytes from a constructor that the side root's loader runs: the root is on that
  // leak's stack, as it is on every stack of the app's, and the leak is still ours.
  const std::string asan = monadoMappedLibrary("libasan.so");
  ASSERT_FALSE(asan.empty()) << "the test process maps no libasan.so";
  const std::string preload = asan + ":" + TELESPHERE_DELIBERATE_LEAK_LIBRARY;
  const MonadoRun run = monadoRunCommand(monadoXrCommand("--preload " + monadoQuote(preload), "--test-scene --frames 12"), 240);
  EXPECT_EQ(run.exit_code, 0) << "the app's own status survives LeakSanitizer's report\n" << run.output;
  EXPECT_NE(run.output.find("focused: yes"), std::string::npos) << run.output;
  const SanitizerFindings findings = monadoFindings(run);
  std::cout << "not ours: " << findings.foreignSummary() << "\n";
  ASSERT_EQ(findings.ours.size(), 1u) << findings.oursText() << "\n--- the whole output\n" << run.output;
  const LeakBlock& leak = findings.ours.front();
  EXPECT_EQ(leak.bytes, 4321);
  EXPECT_NE(leak.allocatingFrame().find("telesphere_test_deliberate_leak"), std::string::npos) << leak.text;
  bool root_on_stack = false;
  for (const std::string& frame : leak.frames) root_on_stack = root_on_stack || frame.find(monadoRoot() + "/") != std::string::npos;
  EXPECT_TRUE(root_on_stack) << "a suppression by the root's location would have hidden this leak:\n" << leak.text;
  EXPECT_TRUE(findings.other_reports.empty()) << findings.oursText();
#endif
}

/// telesphere-robot in the background: simulated arm, synthetic cameras, the link on `port`.
class MonadoRobot {
 public:
  MonadoRobot(int port, const std::string& log_path) {
    const std::string bin = std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-robot";
    const std::string port_text = std::to_string(port);
    pid_ = fork();
    if (pid_ == 0) {
      const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
      execl(bin.c_str(), bin.c_str(), "--insecure", "--sim", "--size", "320x180", "--fps", "15", "--port", port_text.c_str(),
            "--duration", "300", "--stats-period", "1", static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~MonadoRobot() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  MonadoRobot(const MonadoRobot&) = delete;
  MonadoRobot& operator=(const MonadoRobot&) = delete;
  /// SIGINT, then its exit code (-1 when it had to be killed or never started).
  int stop() {
    if (pid_ <= 0) return -1;
    kill(pid_, SIGINT);
    int status = 0;
    for (int i = 0; i < 100; ++i) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = 0;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
};

std::string monadoReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(OpenXrMonado, ShowsTheRobotsFramesSendsHeadTargetsAndFollowsLiveSettings) {
  SKIP_WITHOUT_MONADO_ROOT();
  const fs::path dir = monadoScratch("robot");
  const int port = 27800;
  MonadoRobot robot(port, (dir / "robot.log").string());

  // The console: waits for the app's statistics to come through the robot, then changes the
  // mode and the sphere radius there; the app must follow both live.
  std::atomic<bool> done{false};
  std::atomic<bool> saw_xr_stats{false}, saw_nominal{false}, changed{false};
  std::string console_error;
  std::thread console([&] {
    link::LinkEndpoints endpoints;
    endpoints.base_port = port;
    link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false, .ping_period = std::chrono::milliseconds(200)});
    while (!done.load()) {
      if (const auto state = client.latestRobotState(); state && state->nominal_set()) saw_nominal = true;
      const auto stats = client.latestXrStats();
      if (stats && stats->fps() > 0) saw_xr_stats = true;
      if (saw_xr_stats && !changed) {
        link::proto::ControlRequest mode;
        mode.set_set_visual_mode(link::proto::VISUAL_MODE_ORIENTATION3D);
        link::proto::ControlRequest radius;
        radius.set_set_sphere_radius(2.5);
        const auto a = client.request(mode, std::chrono::milliseconds(3000));
        const auto b = client.request(radius, std::chrono::milliseconds(3000));
        if (!a || !a->ok() || !b || !b->ok()) console_error = "the robot did not accept the console's changes";
        changed = true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });

  const MonadoRun run = monadoRunCommand(
      monadoXrCommand("", "--calib " + monadoQuote(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml") +
                              " --port " + std::to_string(port) + " --video-link udp --frames 120 --readback-dir " +
                              monadoQuote(dir.string()) + " --out " + monadoQuote(dir.string())),
      300);
  done = true;
  console.join();
  const int robot_code = robot.stop();
  const std::string robot_log = monadoReadFile(dir / "robot.log");
  ASSERT_EQ(run.exit_code, 0) << run.output << "\n--- robot\n" << robot_log;
  EXPECT_EQ(robot_code, 0) << robot_log;
  EXPECT_NE(run.output.find("focused: yes"), std::string::npos) << run.output;
  monadoExpectNothingOfOurs(run);
  EXPECT_GE(monadoNumberAfter(run.output, "submitted "), 120) << run.output;

  // Head targets reached the robot: it captured the nominal pose from them and published it.
  EXPECT_NE(robot_log.find("nominal pose captured"), std::string::npos) << robot_log;
  EXPECT_TRUE(saw_nominal.load());
  EXPECT_TRUE(saw_xr_stats.load()) << "the app's statistics did not reach the console through the robot";
  EXPECT_TRUE(changed.load());
  EXPECT_EQ(console_error, "");
  const std::string stats = monadoReadFile(dir / "stats.json");
  EXPECT_NE(stats.find("\"nominal_from_robot\": true"), std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"head_targets_sent\": 0"), std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"stereo_frames_shown\": 0"), std::string::npos) << stats;
  // The frames came over the media path, the one an operator across the Internet uses (the
  // ZeroMQ link's frames are what the offscreen tests show).
  EXPECT_NE(stats.find("\"video_link\": \"udp\""), std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"media_datagrams\": 0"), std::string::npos) << stats;

  // Every image logged; the first ones in the start settings, the last ones in the console's.
  const auto eyes = monadoReadPoses((dir / "poses.csv").string());
  ASSERT_GE(eyes.size(), 240u);
  EXPECT_EQ(eyes.front().mode, "full6d");
  EXPECT_DOUBLE_EQ(eyes.front().radius, 1.0);
  EXPECT_EQ(eyes.back().mode, "orientation3d");
  EXPECT_DOUBLE_EQ(eyes.back().radius, 2.5);

  // Swapchain images against the renderer offscreen, from the very planes the app showed.
  std::vector<LoggedEye> sample;
  for (const LoggedEye& e : eyes)
    if (e.sequence > 0 && (sample.size() < 2 || sample.back().mode != e.mode)) sample.push_back(e);
  sample.push_back(eyes[eyes.size() - 2]);
  sample.push_back(eyes[eyes.size() - 1]);
  const auto calibration = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  ASSERT_TRUE(calibration);
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  ASSERT_TRUE(context) << error;
  xr::render::SphericalRenderer renderer;
  for (const LoggedEye& e : sample) {
    ASSERT_GT(e.sequence, 0u) << e.png;
    char name[80];
    std::snprintf(name, sizeof name, "planes_%06llu_eye%d.yuv", e.sequence, e.eye);
    auto planes = xr::render::readYuvPlanes((dir / name).string(), &error);
    ASSERT_TRUE(planes) << error;
    const auto camera = calib::atResolution(calibration->cameras[std::size_t(e.eye)], planes->width, planes->height, &error);
    ASSERT_TRUE(camera) << error;
    xr::render::GpuCamera gpu(camera->camera, planes->width, planes->height);
    ASSERT_TRUE(gpu.upload(xr::render::SourceImage::yuv(std::make_shared<const xr::render::YuvPlanes>(std::move(*planes))), &error)) << error;
    xr::render::RenderSettings settings;
    settings.mode = telesphere::link::parseVisualMode(e.mode).value();
    settings.radius = e.radius;
    // The image as old as it was when shown: grey past 1 s, with the link's cues over it.
    settings.image_saturation = e.image_saturation;
    ASSERT_TRUE(renderer.prepare(gpu, settings.path, &error)) << error;
    gl::OffscreenTarget target(e.view.width, e.view.height, GL_RGBA8);
    ASSERT_TRUE(renderer.render(gpu, e.view, settings, target.framebuffer(), &error)) << error;
    // The app ran with --insecure: "INSECURE LINK" over every eye.
    auto cues = e.link_state;
    cues.insecure = true;
    xr::frame_loop::drawLinkState(target.framebuffer(), e.view.width, e.view.height, cues, {});
    const auto reference = target.readRgba8();
    const auto png = gl::readPng((dir / e.png).string(), &error);
    ASSERT_TRUE(png) << error;
    ASSERT_EQ(png->rgba.size(), reference.size());
    double sum = 0;
    std::size_t over = 0, count = 0;
    int max = 0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      if (i % 4 == 3) continue;
      const int diff = std::abs(int(png->rgba[i]) - int(reference[i]));
      max = std::max(max, diff);
      sum += diff;
      over += diff > 8 ? 1 : 0;
      ++count;
    }
    std::cout << e.png << " (frame " << e.sequence << ", " << e.mode << ", r " << e.radius << ", shown "
              << e.link_state.image_age_ms << " ms old) vs offscreen: max " << max << ", mean " << sum / double(count)
              << "\n";
    EXPECT_LT(sum / double(count), 0.5) << e.png;
    EXPECT_LT(double(over) / double(count), 0.002) << e.png;
  }
}

}  // namespace
}  // namespace telesphere::test
