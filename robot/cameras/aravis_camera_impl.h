// SPDX-License-Identifier: MIT
/// @brief AravisCamera's inside, shared by its files (private to robot/cameras): the Aravis helpers,
///        the session (an open camera and its stream), and the Impl that the opening
///        (aravis_camera_open.cpp), the stream thread (aravis_camera_stream.cpp) and the public calls
///        (aravis_camera.cpp) share.
#pragma once


#include "robot/cameras/aravis_camera.h"

#include <arv.h>

#include <time.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <thread>

#include "robot/clock/clock.h"
#include "robot/cameras/debayer.h"
#include "robot/cameras/reusable_buffers.h"
#include "robot/cameras/frame_id_tracker.h"
#include "robot/cameras/narrow_samples.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::robot::cameras {


// Named (not anonymous) namespace: Impl has a member of this type, and in unity builds this file
// is included, where GCC's -Wsubobject-linkage rejects anonymous-namespace member types.
namespace aravis_detail {


// Aravis's device list and open calls are process-wide; several cameras open one at a time.
inline std::mutex& aravisSystemMutex() {
  static std::mutex mutex;
  return mutex;
}

/// A layout the camera may send: the 8-bit PixelFormat frames carry, and the bits per sample on the
/// wire (8, or 10–16 in unpacked 16-bit words, narrowed to 8 at capture).
struct AravisLayout {
  ArvPixelFormat arv = ARV_PIXEL_FORMAT_MONO_8;
  const char* name = "";  ///< GenICam name
  PixelFormat format = PixelFormat::kMono8;
  int sample_bits = 8;
  int bytesPerPixel() const { return sample_bits > 8 ? 2 : cameras::bytesPerPixel(format); }
};

inline constexpr AravisLayout kAravisLayouts[] = {
    {ARV_PIXEL_FORMAT_MONO_8, "Mono8", PixelFormat::kMono8, 8},
    {ARV_PIXEL_FORMAT_RGB_8_PACKED, "RGB8", PixelFormat::kRgb8, 8},
    {ARV_PIXEL_FORMAT_BAYER_RG_8, "BayerRG8", PixelFormat::kBayerRG8, 8},
    {ARV_PIXEL_FORMAT_BAYER_GR_8, "BayerGR8", PixelFormat::kBayerGR8, 8},
    {ARV_PIXEL_FORMAT_BAYER_GB_8, "BayerGB8", PixelFormat::kBayerGB8, 8},
    {ARV_PIXEL_FORMAT_BAYER_BG_8, "BayerBG8", PixelFormat::kBayerBG8, 8},
    // Wider sensors, narrowest first (the order open() tries them in when 8 bits are not offered).
    {ARV_PIXEL_FORMAT_MONO_10, "Mono10", PixelFormat::kMono8, 10},
    {ARV_PIXEL_FORMAT_BAYER_RG_10, "BayerRG10", PixelFormat::kBayerRG8, 10},
    {ARV_PIXEL_FORMAT_BAYER_GR_10, "BayerGR10", PixelFormat::kBayerGR8, 10},
    {ARV_PIXEL_FORMAT_BAYER_GB_10, "BayerGB10", PixelFormat::kBayerGB8, 10},
    {ARV_PIXEL_FORMAT_BAYER_BG_10, "BayerBG10", PixelFormat::kBayerBG8, 10},
    {ARV_PIXEL_FORMAT_MONO_12, "Mono12", PixelFormat::kMono8, 12},
    {ARV_PIXEL_FORMAT_BAYER_RG_12, "BayerRG12", PixelFormat::kBayerRG8, 12},
    {ARV_PIXEL_FORMAT_BAYER_GR_12, "BayerGR12", PixelFormat::kBayerGR8, 12},
    {ARV_PIXEL_FORMAT_BAYER_GB_12, "BayerGB12", PixelFormat::kBayerGB8, 12},
    {ARV_PIXEL_FORMAT_BAYER_BG_12, "BayerBG12", PixelFormat::kBayerBG8, 12},
    {ARV_PIXEL_FORMAT_MONO_14, "Mono14", PixelFormat::kMono8, 14},
    {ARV_PIXEL_FORMAT_MONO_16, "Mono16", PixelFormat::kMono8, 16},
    {ARV_PIXEL_FORMAT_BAYER_RG_16, "BayerRG16", PixelFormat::kBayerRG8, 16},
    {ARV_PIXEL_FORMAT_BAYER_GR_16, "BayerGR16", PixelFormat::kBayerGR8, 16},
    {ARV_PIXEL_FORMAT_BAYER_GB_16, "BayerGB16", PixelFormat::kBayerGB8, 16},
    {ARV_PIXEL_FORMAT_BAYER_BG_16, "BayerBG16", PixelFormat::kBayerBG8, 16},
};

inline std::optional<AravisLayout> aravisLayoutOf(ArvPixelFormat format) {
  for (const AravisLayout& layout : kAravisLayouts)
    if (layout.arv == format) return layout;
  return std::nullopt;
}

/// "Mono8, RGB8, BayerRG8/GR8/GB8/BG8 and their 10/12/14/16-bit unpacked forms": for errors.
inline constexpr const char* kAravisLayoutsAccepted =
    "Mono8, RGB8, BayerRG8/GR8/GB8/BG8, or Mono and Bayer at 10, 12, 14 or 16 bits unpacked";

inline const char* aravisBufferStatusName(ArvBufferStatus status) {
  switch (status) {
    case ARV_BUFFER_STATUS_SUCCESS: return "SUCCESS";
    case ARV_BUFFER_STATUS_CLEARED: return "CLEARED";
    case ARV_BUFFER_STATUS_TIMEOUT: return "TIMEOUT";
    case ARV_BUFFER_STATUS_MISSING_PACKETS: return "MISSING_PACKETS";
    case ARV_BUFFER_STATUS_WRONG_PACKET_ID: return "WRONG_PACKET_ID";
    case ARV_BUFFER_STATUS_SIZE_MISMATCH: return "SIZE_MISMATCH";
    case ARV_BUFFER_STATUS_FILLING: return "FILLING";
    case ARV_BUFFER_STATUS_ABORTED: return "ABORTED";
    default: return "UNKNOWN";
  }
}

inline std::int64_t aravisRealtimeNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

/// One device as Aravis lists it.
struct AravisDeviceInfo {
  std::string id, physical_id, address, serial, vendor, model, protocol;
  std::string describe() const {
    std::string s = id;
    s.append(" (").append(vendor).append(" ").append(model).append(", serial ").append(serial);
    s.append(", ").append(protocol).append(")");
    return s;
  }
};

inline std::string aravisStr(const char* s) { return s ? s : ""; }

/// Caller holds aravisSystemMutex().
inline std::vector<AravisDeviceInfo> aravisScanDevices() {
  arv_update_device_list();
  std::vector<AravisDeviceInfo> devices;
  const unsigned n = arv_get_n_devices();
  for (unsigned i = 0; i < n; ++i)
    devices.push_back({aravisStr(arv_get_device_id(i)), aravisStr(arv_get_device_physical_id(i)),
                       aravisStr(arv_get_device_address(i)), aravisStr(arv_get_device_serial_nbr(i)),
                       aravisStr(arv_get_device_vendor(i)), aravisStr(arv_get_device_model(i)),
                       aravisStr(arv_get_device_protocol(i))});
  return devices;
}

inline void aravisOnControlLost(ArvDevice* /*device*/, gpointer flag) {
  static_cast<std::atomic<bool>*>(flag)->store(true);
}


/// Owns an open camera and its stream (RAII; teardown never fails).
struct AravisSession {
  ArvCamera* camera = nullptr;
  ArvStream* stream = nullptr;
  ArvDevice* device = nullptr;  // borrowed from camera
  gulong control_lost_handler = 0;
  std::size_t payload_bytes = 0;  // size of each buffer in the pool
  bool acquiring = false;

  AravisSession() = default;
  AravisSession(const AravisSession&) = delete;
  AravisSession& operator=(const AravisSession&) = delete;
  ~AravisSession() {
    if (acquiring) {
      GError* error = nullptr;
      arv_camera_stop_acquisition(camera, &error);  // a lost camera may not answer: ignored
      g_clear_error(&error);
    }
    if (control_lost_handler != 0) g_signal_handler_disconnect(device, control_lost_handler);
    if (stream) g_object_unref(stream);  // joins Aravis's receive thread
    if (camera) g_object_unref(camera);
  }
};

}  // namespace aravis_detail


using namespace aravis_detail;  // the helpers above, for this class's files

struct AravisCamera::Impl {
  explicit Impl(AravisCameraOptions o) : options(std::move(o)), mapping(options.clock) {}

  AravisCameraOptions options;
  clock::SteadyClock clock;

  // Controlling thread / stream thread (handed over at start and back at stop).
  std::unique_ptr<AravisSession> session;
  std::thread thread;
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> control_lost{false};

  // Guarded by mutex.
  mutable std::mutex mutex;
  std::condition_variable frame_ready;
  std::condition_variable wake;  // stop() interrupts a reconnect backoff
  std::deque<CameraFrame> queue;
  AravisCameraDetails details;
  AravisCameraSettings settings;
  bool running = false;

  // Stream thread only.
  clock::DeviceClockMapping mapping;
  FrameIdTracker frame_ids;
  std::uint64_t incomplete_since_good = 0;
  std::int64_t last_buffer_ns = 0;
  std::int64_t last_drop_log_ns = 0;
  std::uint64_t drops_since_log = 0;
  ReusableBuffers frame_buffers;  ///< the frames' pixels, reused once nobody holds a frame
  std::vector<std::uint8_t> narrowed;  ///< a wide sensor's samples at 8 bits, before the debayer

  std::string label() const {
    std::lock_guard lock(mutex);
    if (!settings.device_id.empty()) return settings.device_id;
    return options.device_id.empty() ? std::string("first camera") : options.device_id;
  }

  void log(const std::string& line) const { std::fprintf(stderr, "AravisCamera '%s': %s\n", label().c_str(), line.c_str()); }

  std::unique_ptr<AravisSession> open(AravisCameraSettings* out_settings, std::string* error);
  void streamLoop();
  void processBuffer(ArvBuffer* buffer);
  void dropBuffer(const char* reason);
  void loseCamera(const std::string& reason);
  bool reopen();
  std::chrono::milliseconds lostTimeout() const;
};

}  // namespace telesphere::robot::cameras
