// SPDX-License-Identifier: MIT
/// @brief AravisCamera against Aravis's in-process fake camera ("Fake_1", no network): open by
///        name and serial, clear errors for a wrong name or size, configure and read back, stream
///        with increasing sequence and host-clock capture times, stop/start, Bayer → RGB8 against a
///        known pattern, 16-bit samples narrowed to 8, incomplete buffers (a frame that does not fit: SIZE_MISMATCH) dropped and
///        counted while the stream goes on, frame-id gaps counted as lost, hardware stamps on a
///        foreign clock mapped to the host, and the camera lost (control-lost, interface gone) and
///        re-opened.
#include <arv.h>
#include <gtest/gtest.h>
#include <time.h>

#include <array>
#include <atomic>
#include <mutex>
#include <thread>

#include "robot/cameras/aravis_camera.h"
#include "robot/clock/clock.h"
#include "robot/cameras/debayer.h"
#include "robot/cameras/narrow_samples.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

/// Eight 8-px colour bars; Bayer frames are this image sampled through the mosaic.
constexpr std::array<std::array<int, 3>, 8> kBars = {{{0, 0, 0},
                                                      {255, 255, 255},
                                                      {255, 0, 0},
                                                      {0, 255, 0},
                                                      {0, 0, 255},
                                                      {255, 255, 0},
                                                      {0, 255, 255},
                                                      {255, 0, 255}}};
std::array<int, 3> barColour(int x) { return kBars[(x / 8) % kBars.size()]; }

int mosaicChannel(ArvPixelFormat format, int x, int y) {
  const char* cell = format == ARV_PIXEL_FORMAT_BAYER_RG_8   ? "RGGB"
                     : format == ARV_PIXEL_FORMAT_BAYER_GR_8 ? "GRBG"
                     : format == ARV_PIXEL_FORMAT_BAYER_GB_8 ? "GBRG"
                                                              : "BGGR";
  const char c = cell[(y & 1) * 2 + (x & 1)];
  return c == 'R' ? 0 : c == 'G' ? 1 : 2;
}

std::int64_t monotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

/// What a 16-bit fake camera draws at (x, y): every word value crossed many times over the image.
int wideSample(int x, int y) { return (x * 257 + y * 4099) & 0xFFFF; }

/// What the fake camera draws, and the fakes' devices (held with a GObject reference).
struct FakeScene {
  std::atomic<int> skip_every{0};          // every n-th frame id jumps by skip_amount
  std::atomic<int> skip_amount{0};
  std::atomic<std::int64_t> hw_offset_ns{0};  // ≠ 0: stamps = CLOCK_MONOTONIC + offset
  std::atomic<std::uint64_t> filled{0};
  std::mutex mutex;
  ArvDevice* device = nullptr;
  std::atomic<int> opens{0};

  ~FakeScene() {
    if (device) g_object_unref(device);
  }
  ArvDevice* currentDevice() {
    std::lock_guard lock(mutex);
    return device;
  }
  ArvFakeCamera* currentFake() { return arv_fake_device_get_fake_camera(ARV_FAKE_DEVICE(currentDevice())); }

  static void fill(ArvBuffer* buffer, void* data, guint32 /*exposure_us*/, guint32 /*gain*/, ArvPixelFormat format) {
    auto* scene = static_cast<FakeScene*>(data);
    const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
    auto* p = static_cast<std::uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
    const bool bayer = format == ARV_PIXEL_FORMAT_BAYER_RG_8 || format == ARV_PIXEL_FORMAT_BAYER_GR_8 ||
                       format == ARV_PIXEL_FORMAT_BAYER_GB_8 || format == ARV_PIXEL_FORMAT_BAYER_BG_8;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (format == ARV_PIXEL_FORMAT_MONO_16) {  // little-endian words
          p[2 * (y * w + x)] = static_cast<std::uint8_t>(wideSample(x, y) & 0xFF);
          p[2 * (y * w + x) + 1] = static_cast<std::uint8_t>(wideSample(x, y) >> 8);
          continue;
        }
        p[y * w + x] = static_cast<std::uint8_t>(bayer ? barColour(x)[mosaicChannel(format, x, y)] : (x + 2 * y) & 0xFF);
      }
    const std::uint64_t n = scene->filled++;
    if (const int every = scene->skip_every.load(); every > 0)
      arv_buffer_set_frame_id(buffer, arv_buffer_get_frame_id(buffer) + scene->skip_amount.load() * (n / every));
    if (const std::int64_t offset = scene->hw_offset_ns.load(); offset != 0)
      arv_buffer_set_timestamp(buffer, static_cast<guint64>(monotonicNs() + offset));
  }

  /// AravisCameraOptions::on_open: draw our scene, remember the device.
  std::function<void(void*)> hook() {
    return [this](void* arv_camera) {
      ArvDevice* opened = arv_camera_get_device(ARV_CAMERA(arv_camera));
      ASSERT_TRUE(ARV_IS_FAKE_DEVICE(opened));
      arv_fake_camera_set_fill_pattern(arv_fake_device_get_fake_camera(ARV_FAKE_DEVICE(opened)), &FakeScene::fill, this);
      std::lock_guard lock(mutex);
      if (device) g_object_unref(device);
      device = ARV_DEVICE(g_object_ref(opened));
      ++opens;
    };
  }
};

class AravisCameraFake : public ::testing::Test {
 protected:
  void SetUp() override { cameras::AravisCamera::enableFakeInterface(); }

  static cameras::AravisCameraOptions fakeOptions(FakeScene& scene) {
    cameras::AravisCameraOptions o;
    o.device_id = "Fake_1";
    o.width = 640;
    o.height = 480;
    o.pixel_format = cameras::PixelFormat::kMono8;
    o.frame_rate_hz = 50;
    o.exposure_us = 4000;
    o.gain = 2;
    o.buffer_count = 6;
    o.queue_depth = 16;
    o.on_open = scene.hook();
    return o;
  }

  /// Bounded wait for a condition on the camera's counters (polled; the stream thread updates them).
  template <typename Predicate>
  static bool waitFor(Predicate predicate, std::chrono::milliseconds limit = 15s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!predicate()) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(5ms);
    }
    return true;
  }
};

TEST_F(AravisCameraFake, OpensByNameConfiguresAndReadsBack) {
  FakeScene scene;
  cameras::AravisCamera camera(fakeOptions(scene));
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  const cameras::AravisCameraSettings s = camera.settings();
  EXPECT_EQ(s.device_id, "Fake_1");
  EXPECT_EQ(camera.name(), "Fake_1");
  EXPECT_EQ(s.serial_number, "1");
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 480);
  EXPECT_EQ(s.camera_format, cameras::PixelFormat::kMono8);
  EXPECT_EQ(s.output_format, cameras::PixelFormat::kMono8);
  EXPECT_NEAR(s.frame_rate_hz, 50.0, 0.5);
  EXPECT_NEAR(s.exposure_us, 4000.0, 1.0);
  EXPECT_NEAR(s.gain, 2.0, 0.01);
  EXPECT_EQ(scene.opens, 1);
  camera.stop();
}

TEST_F(AravisCameraFake, OpensBySerialNumber) {
  FakeScene scene;
  cameras::AravisCameraOptions o = fakeOptions(scene);
  o.device_id = "1";  // the fake's serial; Aravis itself would take "1" for an address
  cameras::AravisCamera camera(o);
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  EXPECT_EQ(camera.settings().device_id, "Fake_1");
}

TEST_F(AravisCameraFake, WrongNameGivesAnErrorNamingItAndListingTheDevices) {
  FakeScene scene;
  cameras::AravisCameraOptions o = fakeOptions(scene);
  o.device_id = "Basler-99999999";
  cameras::AravisCamera camera(o);
  std::string error;
  EXPECT_FALSE(camera.start(&error));
  EXPECT_NE(error.find("Basler-99999999"), std::string::npos) << error;
  EXPECT_NE(error.find("not found"), std::string::npos) << error;
  EXPECT_NE(error.find("Fake_1"), std::string::npos) << error;
  EXPECT_EQ(camera.stats().last_error, error);
  EXPECT_FALSE(camera.nextFrame(10ms).has_value());
  const auto devices = cameras::AravisCamera::listDevices();
  ASSERT_FALSE(devices.empty());
  EXPECT_NE(devices.front().find("Fake_1"), std::string::npos);
}

TEST_F(AravisCameraFake, SettingsTheCameraRefusesAreReported) {
  FakeScene scene;
  cameras::AravisCameraOptions o = fakeOptions(scene);
  o.frame_rate_hz = 5000;  // the fake's AcquisitionFrameRate ends at 1000 Hz
  cameras::AravisCamera camera(o);
  std::string error;
  EXPECT_FALSE(camera.start(&error));
  EXPECT_NE(error.find("Fake_1"), std::string::npos) << error;
  EXPECT_NE(error.find("AcquisitionFrameRate"), std::string::npos) << error;
}

TEST_F(AravisCameraFake, StreamsFramesWithIncreasingSequenceAndHostCaptureTimes) {
  FakeScene scene;
  cameras::AravisCamera camera(fakeOptions(scene));
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  clock::SteadyClock host;
  std::uint64_t last_sequence = 0;
  for (int i = 0; i < 20; ++i) {
    const auto frame = camera.nextFrame(3s);
    ASSERT_TRUE(frame.has_value()) << "frame " << i << ": " << camera.stats().last_error;
    const std::int64_t now_ns = host.nowNs();
    EXPECT_EQ(frame->format, cameras::PixelFormat::kMono8);
    EXPECT_EQ(frame->width, 640);
    EXPECT_EQ(frame->height, 480);
    EXPECT_EQ(frame->stride_bytes, 640);
    EXPECT_EQ(frame->exposure_us, 4000u);
    EXPECT_TRUE(frame->timestamp_from_hardware);
    ASSERT_EQ(frame->pixels->size(), 640u * 480u);
    EXPECT_EQ((*frame->pixels)[5 * 640 + 7], (7 + 2 * 5) & 0xFF);  // the scene's ramp
    // Captured in the past (mid-exposure, before arrival), and recently.
    EXPECT_LE(frame->capture_ns, now_ns);
    EXPECT_GT(frame->capture_ns, now_ns - 1'000'000'000);
    if (i > 0) {
      EXPECT_GT(frame->sequence, last_sequence);
    }
    last_sequence = frame->sequence;
  }
  const cameras::CameraStats stats = camera.stats();
  EXPECT_EQ(stats.frames, 20u);
  EXPECT_EQ(stats.incomplete, 0u);
  EXPECT_EQ(stats.lost, 0u);
  EXPECT_EQ(stats.reconnects, 0u);
  EXPECT_TRUE(stats.last_error.empty()) << stats.last_error;
  const cameras::AravisCameraDetails details = camera.details();
  EXPECT_GT(details.clock_pairs, 0u);
  // The fake stamps with CLOCK_REALTIME: the mapped offset is realtime → steady.
  const std::int64_t realtime_to_steady_ns =
      host.nowNs() - std::chrono::duration_cast<std::chrono::nanoseconds>(
                         std::chrono::system_clock::now().time_since_epoch()).count();
  EXPECT_NEAR(static_cast<double>(details.hw_to_host_offset_ns), static_cast<double>(realtime_to_steady_ns), 5e8);
}

TEST_F(AravisCameraFake, StopsAndStartsAgain) {
  FakeScene scene;
  cameras::AravisCamera camera(fakeOptions(scene));
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  ASSERT_TRUE(camera.nextFrame(3s).has_value());
  camera.stop();
  camera.stop();  // idempotent
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(camera.nextFrame(5s).has_value());
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 4s) << "nextFrame must return at once when stopped";
  ASSERT_TRUE(camera.start(&error)) << error;
  EXPECT_EQ(scene.opens, 2);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(camera.nextFrame(3s).has_value()) << i;
  EXPECT_EQ(camera.stats().frames, 3u);  // counters start afresh with start()
}

TEST_F(AravisCameraFake, BayerIsDebayeredToTheKnownColourBars) {
  for (cameras::PixelFormat layout : {cameras::PixelFormat::kBayerRG8, cameras::PixelFormat::kBayerGR8, cameras::PixelFormat::kBayerGB8, cameras::PixelFormat::kBayerBG8}) {
    SCOPED_TRACE(cameras::pixelFormatName(layout));
    FakeScene scene;
    cameras::AravisCameraOptions o = fakeOptions(scene);
    o.pixel_format = layout;
    o.width = 128;
    o.height = 64;
    cameras::AravisCamera camera(o);
    std::string error;
    ASSERT_TRUE(camera.start(&error)) << error;
    EXPECT_EQ(camera.settings().camera_format, layout);
    EXPECT_EQ(camera.settings().output_format, cameras::PixelFormat::kRgb8);
    const auto frame = camera.nextFrame(3s);
    ASSERT_TRUE(frame.has_value()) << camera.stats().last_error;
    ASSERT_EQ(frame->format, cameras::PixelFormat::kRgb8);
    ASSERT_EQ(frame->stride_bytes, 128 * 3);
    ASSERT_EQ(frame->pixels->size(), 128u * 64u * 3u);
    int checked = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 128; ++x) {
        if (x % 8 == 0 || x % 8 == 7) continue;  // bar edges blend
        const std::uint8_t* p = &(*frame->pixels)[(y * 128 + x) * 3];
        const auto want = barColour(x);
        ASSERT_EQ(p[0], want[0]) << x << "," << y;
        ASSERT_EQ(p[1], want[1]) << x << "," << y;
        ASSERT_EQ(p[2], want[2]) << x << "," << y;
        ++checked;
      }
    EXPECT_EQ(checked, 128 * 64 * 6 / 8);
  }
}

TEST_F(AravisCameraFake, RawBayerIsDeliveredUnchangedWhenDebayerIsOff) {
  FakeScene scene;
  cameras::AravisCameraOptions o = fakeOptions(scene);
  o.pixel_format = cameras::PixelFormat::kBayerGB8;
  o.width = 64;
  o.height = 32;
  o.debayer = false;
  cameras::AravisCamera camera(o);
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  const auto frame = camera.nextFrame(3s);
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->format, cameras::PixelFormat::kBayerGB8);
  ASSERT_EQ(frame->pixels->size(), 64u * 32u);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x)
      ASSERT_EQ((*frame->pixels)[y * 64 + x], barColour(x)[mosaicChannel(ARV_PIXEL_FORMAT_BAYER_GB_8, x, y)]);
}

TEST_F(AravisCameraFake, SixteenBitSamplesAreNarrowedToEightBitsAtCapture) {
  // The fake camera streams Mono16 (a sensor at full depth); frames carry Mono8, each sample the
  // rounded 8-bit value of its word. BayerXX10/12/16 go the same way, then to the debayer.
  FakeScene scene;
  cameras::AravisCameraOptions o = fakeOptions(scene);
  o.pixel_format.reset();
  o.on_open = [draw = scene.hook()](void* arv_camera) {
    draw(arv_camera);
    GError* error = nullptr;
    arv_camera_set_pixel_format(ARV_CAMERA(arv_camera), ARV_PIXEL_FORMAT_MONO_16, &error);
    EXPECT_EQ(error, nullptr) << error->message;
    g_clear_error(&error);
  };
  cameras::AravisCamera camera(o);
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  EXPECT_EQ(camera.settings().camera_format, cameras::PixelFormat::kMono8);
  EXPECT_EQ(camera.settings().camera_sample_bits, 16);
  EXPECT_EQ(camera.settings().output_format, cameras::PixelFormat::kMono8);
  for (int n = 0; n < 3; ++n) {
    const std::optional<cameras::CameraFrame> frame = camera.nextFrame(5s);
    ASSERT_TRUE(frame) << camera.stats().last_error;
    ASSERT_EQ(frame->format, cameras::PixelFormat::kMono8);
    ASSERT_EQ(frame->width, 640);
    ASSERT_EQ(frame->stride_bytes, 640);
    ASSERT_EQ(frame->pixels->size(), 640u * 480u);
    int mismatches = 0;
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x) {
        const int want = cameras::narrowSampleTo8Bits(static_cast<std::uint16_t>(wideSample(x, y)), 16);
        if ((*frame->pixels)[y * 640 + x] != want && ++mismatches <= 3)
          ADD_FAILURE() << "at " << x << "," << y << ": " << int{(*frame->pixels)[y * 640 + x]} << ", want " << want;
      }
    EXPECT_EQ(mismatches, 0);
  }
  EXPECT_EQ(camera.details().stats.incomplete, 0u);
  camera.stop();
}

TEST_F(AravisCameraFake, IncompleteFramesAreDroppedCountedAndTheStreamResumes) {
  // The camera starts sending frames larger than the buffers (as if it stopped mid-frame and
  // restarted with another size): Aravis marks them SIZE_MISMATCH; they must be dropped with a
  // reason, nothing may crash, and the next good frame must come through.
  FakeScene scene;
  cameras::AravisCamera camera(fakeOptions(scene));
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  ASSERT_TRUE(camera.nextFrame(3s).has_value());
  ArvFakeCamera* fake = scene.currentFake();
  ASSERT_TRUE(arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_WIDTH, 2048));
  EXPECT_TRUE(waitFor([&] { return camera.stats().incomplete >= 3; })) << camera.stats().incomplete;
  ASSERT_TRUE(arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_WIDTH, 640));
  // Drain what was queued before the switch back; then a fresh good frame must arrive.
  while (camera.nextFrame(0ms)) {
  }
  const auto frame = camera.nextFrame(3s);
  ASSERT_TRUE(frame.has_value()) << camera.stats().last_error;
  EXPECT_EQ(frame->width, 640);
  const cameras::AravisCameraDetails details = camera.details();
  EXPECT_GE(details.dropped_by_reason.at("SIZE_MISMATCH"), 3u);
  EXPECT_EQ(details.stats.lost, 0u) << "dropped frames must not be counted twice as lost";
  EXPECT_EQ(details.stats.reconnects, 0u);
}

TEST_F(AravisCameraFake, FrameIdGapsAreCountedAsLost) {
  FakeScene scene;
  scene.skip_every = 5;  // every 5th frame the id jumps by 3: 3 frames lost
  scene.skip_amount = 3;
  cameras::AravisCamera camera(fakeOptions(scene));
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  std::uint64_t last = 0;
  int gaps = 0;
  for (int i = 0; i < 30; ++i) {
    const auto frame = camera.nextFrame(3s);
    ASSERT_TRUE(frame.has_value()) << i;
    if (i > 0) {
      const std::uint64_t step = frame->sequence - last;
      EXPECT_TRUE(step == 1 || step == 4) << "step " << step;
      gaps += step == 4;
    }
    last = frame->sequence;
  }
  EXPECT_GE(gaps, 4);
  const std::uint64_t lost = camera.stats().lost;
  EXPECT_EQ(lost % 3, 0u);
  EXPECT_GE(lost, 3u * gaps);
}

TEST_F(AravisCameraFake, HardwareStampsOnAForeignClockAreMappedToTheHost) {
  FakeScene scene;
  scene.hw_offset_ns = 7'000'000'000;  // camera clock = host steady clock + 7 s
  cameras::AravisCamera camera(fakeOptions(scene));
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  clock::SteadyClock host;
  for (int i = 0; i < 25; ++i) {
    const auto frame = camera.nextFrame(3s);
    ASSERT_TRUE(frame.has_value());
    const std::int64_t now_ns = host.nowNs();
    ASSERT_TRUE(frame->timestamp_from_hardware);
    EXPECT_LE(frame->capture_ns, now_ns);
    EXPECT_GT(frame->capture_ns, now_ns - 1'000'000'000);
  }
  // t_host − t_hw ≈ −7 s (+ the tiny fake arrival delay).
  EXPECT_NEAR(static_cast<double>(camera.details().hw_to_host_offset_ns), -7e9, 5e7);
}

TEST_F(AravisCameraFake, LostCameraIsReopenedWhenItComesBack) {
  FakeScene scene;
  cameras::AravisCameraOptions o = fakeOptions(scene);
  o.reconnect_backoff_min = 10ms;
  o.reconnect_backoff_max = 50ms;
  cameras::AravisCamera camera(o);
  std::string error;
  ASSERT_TRUE(camera.start(&error)) << error;
  ASSERT_TRUE(camera.nextFrame(3s).has_value());

  // The camera disappears: its interface goes away and the device reports control lost.
  struct ReEnable {
    ~ReEnable() { arv_enable_interface("Fake"); }
  } re_enable;
  arv_disable_interface("Fake");
  g_signal_emit_by_name(scene.currentDevice(), "control-lost");
  EXPECT_TRUE(waitFor([&] { return camera.details().reconnect_attempts >= 2; }));
  cameras::CameraStats stats = camera.stats();
  EXPECT_NE(stats.last_error.find("camera lost"), std::string::npos) << stats.last_error;
  EXPECT_NE(stats.last_error.find("not found"), std::string::npos) << stats.last_error;
  EXPECT_EQ(stats.reconnects, 0u);
  while (camera.nextFrame(0ms)) {
  }
  EXPECT_FALSE(camera.nextFrame(200ms).has_value()) << "no frames while the camera is gone";

  // It comes back.
  arv_enable_interface("Fake");
  EXPECT_TRUE(waitFor([&] { return camera.stats().reconnects == 1; }));
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(camera.nextFrame(3s).has_value()) << i;
  stats = camera.stats();
  EXPECT_TRUE(stats.last_error.empty()) << stats.last_error;
  EXPECT_EQ(stats.reconnects, 1u);
  EXPECT_EQ(scene.opens, 2);
  EXPECT_EQ(camera.settings().width, 640);  // configured again on re-open
}

}  // namespace
}  // namespace telesphere::robot
