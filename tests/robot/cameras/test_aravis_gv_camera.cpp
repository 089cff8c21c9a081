// SPDX-License-Identifier: MIT
/// @brief AravisCamera against arv-fake-gv-camera-0.8 over real GigE Vision packets (a veth pair
///        into a network namespace, set up by tests/robot/cameras/aravis_gv_test.sh, which needs root):
///        streams with the camera dropping packets (its -r option), drops and counts the
///        incomplete frames while good ones keep coming; the camera process is killed and
///        restarted and AravisCamera re-opens it. Skipped with the reason when not run by the script.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "robot/cameras/aravis_camera.h"
#include "robot/clock/clock.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

std::string gvEnv(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

/// arv-fake-gv-camera-0.8 inside the test's network namespace, as a child process.
class FakeGvCameraProcess {
 public:
  FakeGvCameraProcess(std::string netns, std::string iface, std::string serial, std::string loss_per_mille)
      : argv_{"ip", "netns", "exec", std::move(netns), "arv-fake-gv-camera-0.8", "-i", std::move(iface),
              "-s", std::move(serial), "-r", std::move(loss_per_mille)} {}
  ~FakeGvCameraProcess() { kill(); }

  bool start() {
    std::vector<char*> args;  // built before fork: the child may only exec
    for (std::string& a : argv_) args.push_back(a.data());
    args.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      execvp(args[0], args.data());
      _exit(127);
    }
    return pid_ > 0;
  }
  void kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);  // ip netns exec execs the camera: this pid is the camera
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  std::vector<std::string> argv_;
  pid_t pid_ = -1;
};

template <typename Predicate>
bool gvWaitFor(Predicate predicate, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

TEST(AravisCameraGigEVision, StreamsWithPacketLossAndReopensARestartedCamera) {
  const std::string netns = gvEnv("TELESPHERE_ARAVIS_GV_NETNS"), iface = gvEnv("TELESPHERE_ARAVIS_GV_IFACE");
  const std::string serial = gvEnv("TELESPHERE_ARAVIS_GV_SERIAL"), loss = gvEnv("TELESPHERE_ARAVIS_GV_LOSS");
  if (netns.empty() || iface.empty() || serial.empty() || loss.empty())
    GTEST_SKIP() << "needs the network namespace that tests/robot/cameras/aravis_gv_test.sh sets up (as root); "
                    "ctest runs it as aravis_gv_camera";
  FakeGvCameraProcess camera_process(netns, iface, serial, loss);
  ASSERT_TRUE(camera_process.start());

  cameras::AravisCameraOptions o;
  o.device_id = serial;  // by serial number: Aravis names the device "Aravis-Fake-<serial>"
  o.width = 640;
  o.height = 480;
  o.pixel_format = cameras::PixelFormat::kMono8;
  o.frame_rate_hz = 30;
  o.exposure_us = 2000;
  o.queue_depth = 16;
  o.reconnect_backoff_min = 50ms;
  o.reconnect_backoff_max = 500ms;
  cameras::AravisCamera camera(o);
  std::string error;
  // The camera process needs a moment before it answers discovery.
  ASSERT_TRUE(gvWaitFor([&] { return camera.start(&error); }, 20s)) << error;
  EXPECT_EQ(camera.settings().device_id, "Aravis-Fake-" + serial);
  EXPECT_EQ(camera.settings().width, 640);

  clock::SteadyClock host;
  auto collect = [&](int wanted, std::chrono::seconds limit) {
    int good = 0;
    std::uint64_t last_sequence = 0;
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (good < wanted && std::chrono::steady_clock::now() < deadline) {
      const auto frame = camera.nextFrame(500ms);
      if (!frame) continue;
      const std::int64_t now_ns = host.nowNs();
      EXPECT_EQ(frame->width, 640);
      EXPECT_EQ(frame->pixels->size(), 640u * 480u);
      EXPECT_TRUE(frame->timestamp_from_hardware);
      EXPECT_LE(frame->capture_ns, now_ns);
      EXPECT_GT(frame->capture_ns, now_ns - 1'000'000'000);
      if (good > 0) {
        EXPECT_GT(frame->sequence, last_sequence);
      }
      last_sequence = frame->sequence;
      ++good;
    }
    return good;
  };
  EXPECT_EQ(collect(20, 30s), 20);
  cameras::AravisCameraDetails details = camera.details();
  std::printf("GigE Vision fake, %s per mille packets lost: %llu good frames, %llu incomplete, %llu lost; drift %.2f ppm\n",
              loss.c_str(), static_cast<unsigned long long>(details.stats.frames),
              static_cast<unsigned long long>(details.stats.incomplete),
              static_cast<unsigned long long>(details.stats.lost), details.clock_drift_ppm);
  for (const auto& [reason, count] : details.dropped_by_reason)
    std::printf("  dropped %s: %llu\n", reason.c_str(), static_cast<unsigned long long>(count));
  if (std::atoi(loss.c_str()) >= 2) {
    // ~220 packets a frame: with ≥ 2 ‰ lost, most frames miss one.
    EXPECT_GT(details.stats.incomplete, 0u);
    EXPECT_GT(details.dropped_by_reason.count("MISSING_PACKETS") + details.dropped_by_reason.count("TIMEOUT"), 0u);
  }

  // The camera goes away (process killed: no heartbeat answers, no packets) and comes back.
  camera_process.kill();
  EXPECT_TRUE(gvWaitFor([&] { return !camera.stats().last_error.empty(); }, 20s));
  EXPECT_NE(camera.stats().last_error.find("camera lost"), std::string::npos) << camera.stats().last_error;
  ASSERT_TRUE(camera_process.start());
  EXPECT_TRUE(gvWaitFor([&] { return camera.stats().reconnects >= 1; }, 30s)) << camera.stats().last_error;
  EXPECT_EQ(collect(10, 30s), 10);
  EXPECT_TRUE(camera.stats().last_error.empty()) << camera.stats().last_error;
  camera.stop();
}

}  // namespace
}  // namespace telesphere::robot
