// SPDX-License-Identifier: MIT
/// @brief AravisCamera: Aravis 0.8 session (open, configure, buffer pool), the stream thread
///        (drop, count, map time, debayer, queue) and re-opening a lost camera.
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
#include "robot/cameras/frame_id_tracker.h"

namespace telesphere::robot {
namespace {

// Aravis's device list and open calls are process-wide; several cameras open one at a time.
std::mutex& aravisSystemMutex() {
  static std::mutex mutex;
  return mutex;
}

ArvPixelFormat aravisPixelFormat(PixelFormat format) {
  switch (format) {
    case PixelFormat::kMono8: return ARV_PIXEL_FORMAT_MONO_8;
    case PixelFormat::kRgb8: return ARV_PIXEL_FORMAT_RGB_8_PACKED;
    case PixelFormat::kBayerRG8: return ARV_PIXEL_FORMAT_BAYER_RG_8;
    case PixelFormat::kBayerGR8: return ARV_PIXEL_FORMAT_BAYER_GR_8;
    case PixelFormat::kBayerGB8: return ARV_PIXEL_FORMAT_BAYER_GB_8;
    case PixelFormat::kBayerBG8: return ARV_PIXEL_FORMAT_BAYER_BG_8;
  }
  return ARV_PIXEL_FORMAT_MONO_8;
}

std::optional<PixelFormat> aravisToPixelFormat(ArvPixelFormat format) {
  for (PixelFormat f : {PixelFormat::kMono8, PixelFormat::kRgb8, PixelFormat::kBayerRG8, PixelFormat::kBayerGR8,
                        PixelFormat::kBayerGB8, PixelFormat::kBayerBG8})
    if (aravisPixelFormat(f) == format) return f;
  return std::nullopt;
}

const char* aravisBufferStatusName(ArvBufferStatus status) {
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

std::int64_t aravisRealtimeNs() {
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

std::string aravisStr(const char* s) { return s ? s : ""; }

/// Caller holds aravisSystemMutex().
std::vector<AravisDeviceInfo> aravisScanDevices() {
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

void aravisOnControlLost(ArvDevice* /*device*/, gpointer flag) {
  static_cast<std::atomic<bool>*>(flag)->store(true);
}

}  // namespace

// Named (not anonymous) namespace: Impl has a member of this type, and in unity builds this file
// is included, where GCC's -Wsubobject-linkage rejects anonymous-namespace member types.
namespace aravis_detail {

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

using aravis_detail::AravisSession;

struct AravisCamera::Impl {
  explicit Impl(AravisCameraOptions o) : options(std::move(o)), mapping(options.clock) {}

  AravisCameraOptions options;
  SteadyClock clock;

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
  DeviceClockMapping mapping;
  FrameIdTracker frame_ids;
  std::uint64_t incomplete_since_good = 0;
  std::int64_t last_buffer_ns = 0;
  std::int64_t last_drop_log_ns = 0;
  std::uint64_t drops_since_log = 0;

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

std::unique_ptr<AravisSession> AravisCamera::Impl::open(AravisCameraSettings* out, std::string* error) {
  const std::string wanted = options.device_id.empty() ? std::string("(first found)") : options.device_id;
  auto fail = [&](const std::string& message) -> std::unique_ptr<AravisSession> {
    if (error) *error = "AravisCamera '" + wanted + "': " + message;
    return nullptr;
  };
  GError* gerror = nullptr;
  auto failed = [&](const char* what, std::string* message) {
    if (!gerror) return false;
    *message = std::string(what) + ": " + gerror->message;
    g_clear_error(&gerror);
    return true;
  };

  auto session = std::make_unique<AravisSession>();
  {
    std::lock_guard lock(aravisSystemMutex());
    const std::vector<AravisDeviceInfo> devices = aravisScanDevices();
    const AravisDeviceInfo* found = nullptr;
    for (const AravisDeviceInfo& d : devices)
      if (options.device_id.empty() || d.id == options.device_id || d.serial == options.device_id ||
          d.physical_id == options.device_id || d.address == options.device_id) {
        found = &d;
        break;
      }
    if (!found) {
      std::string message = "camera not found; ";
      if (devices.empty()) {
        message += "no devices found (GigE Vision, USB3 Vision; the in-process fake camera only when enabled)";
      } else {
        message += std::to_string(devices.size()) + " device(s) found:";
        for (const AravisDeviceInfo& d : devices) message.append(" ").append(d.describe()).append(";");
        message.pop_back();
      }
      return fail(message);
    }
    out->device_id = found->id;
    out->serial_number = found->serial;
    out->model = found->vendor + " " + found->model;
    session->camera = arv_camera_new(found->id.c_str(), &gerror);
    std::string message;
    if (failed(("cannot open " + found->describe()).c_str(), &message) || !session->camera) {
      session->camera = nullptr;
      return fail(message.empty() ? "cannot open " + found->describe() : message);
    }
  }
  ArvCamera* camera = session->camera;
  session->device = arv_camera_get_device(camera);
  std::string message;

  arv_camera_set_acquisition_mode(camera, ARV_ACQUISITION_MODE_CONTINUOUS, &gerror);
  if (failed("AcquisitionMode Continuous", &message)) return fail(message);

  if (options.pixel_format) {
    const char* wanted_format = pixelFormatName(*options.pixel_format);
    guint n = 0;
    const char** available = arv_camera_dup_available_pixel_formats_as_strings(camera, &n, &gerror);
    if (failed("PixelFormat list", &message)) return fail(message);
    std::string list;
    bool supported = false;
    for (guint i = 0; i < n; ++i) {
      list.append(i ? ", " : "").append(available[i]);
      supported = supported || std::string(available[i]) == wanted_format;
    }
    g_free(available);
    if (!supported) return fail(std::string("PixelFormat ") + wanted_format + " not offered; the camera has: " + list);
    arv_camera_set_pixel_format(camera, aravisPixelFormat(*options.pixel_format), &gerror);
    if (failed("PixelFormat", &message)) return fail(message);
  }
  const ArvPixelFormat camera_format = arv_camera_get_pixel_format(camera, &gerror);
  if (failed("PixelFormat read-back", &message)) return fail(message);
  const std::optional<PixelFormat> format = aravisToPixelFormat(camera_format);
  if (!format) {
    const char* name = arv_camera_get_pixel_format_as_string(camera, nullptr);
    return fail(std::string("camera PixelFormat ") + (name ? name : "?") +
                " is not one of Mono8, RGB8, BayerRG8/GR8/GB8/BG8; set options.pixel_format");
  }
  out->camera_format = *format;
  out->output_format = (isBayer(*format) && options.debayer) ? PixelFormat::kRgb8 : *format;

  if (options.width > 0 || options.height > 0) {
    gint x = 0, y = 0, w = 0, h = 0;
    arv_camera_get_region(camera, &x, &y, &w, &h, &gerror);
    if (failed("region read", &message)) return fail(message);
    const gint want_w = options.width > 0 ? options.width : w;
    const gint want_h = options.height > 0 ? options.height : h;
    arv_camera_set_region(camera, 0, 0, want_w, want_h, &gerror);
    if (failed("Width/Height", &message)) return fail(message);
    arv_camera_get_region(camera, &x, &y, &w, &h, &gerror);
    if (failed("region read-back", &message)) return fail(message);
    if (w != want_w || h != want_h) {
      gint w_min = 0, w_max = 0, h_min = 0, h_max = 0;
      arv_camera_get_width_bounds(camera, &w_min, &w_max, nullptr);
      arv_camera_get_height_bounds(camera, &h_min, &h_max, nullptr);
      return fail("Width×Height " + std::to_string(want_w) + "×" + std::to_string(want_h) +
                  " not accepted (camera set " + std::to_string(w) + "×" + std::to_string(h) + "; width " +
                  std::to_string(w_min) + ".." + std::to_string(w_max) + ", height " + std::to_string(h_min) +
                  ".." + std::to_string(h_max) + ")");
    }
  }
  {
    gint x = 0, y = 0;
    arv_camera_get_region(camera, &x, &y, &out->width, &out->height, &gerror);
    if (failed("region read-back", &message)) return fail(message);
  }

  if (options.exposure_us > 0) {
    if (arv_camera_is_exposure_auto_available(camera, nullptr)) {
      arv_camera_set_exposure_time_auto(camera, ARV_AUTO_OFF, &gerror);
      if (failed("ExposureAuto Off", &message)) return fail(message);
    }
    arv_camera_set_exposure_time(camera, options.exposure_us, &gerror);
    if (failed("ExposureTime", &message)) return fail(message);
  }
  if (arv_camera_is_exposure_time_available(camera, nullptr)) {
    out->exposure_us = arv_camera_get_exposure_time(camera, &gerror);
    if (failed("ExposureTime read-back", &message)) return fail(message);
    if (options.exposure_us > 0 && std::abs(out->exposure_us - options.exposure_us) > 0.01 * options.exposure_us + 1)
      return fail("ExposureTime " + std::to_string(options.exposure_us) + " us not accepted (camera has " +
                  std::to_string(out->exposure_us) + " us)");
  }
  if (options.gain >= 0) {
    if (arv_camera_is_gain_auto_available(camera, nullptr)) {
      arv_camera_set_gain_auto(camera, ARV_AUTO_OFF, &gerror);
      if (failed("GainAuto Off", &message)) return fail(message);
    }
    arv_camera_set_gain(camera, options.gain, &gerror);
    if (failed("Gain", &message)) return fail(message);
  }
  if (arv_camera_is_gain_available(camera, nullptr)) {
    out->gain = arv_camera_get_gain(camera, &gerror);
    if (failed("Gain read-back", &message)) return fail(message);
    if (options.gain >= 0 && std::abs(out->gain - options.gain) > 0.01 * options.gain + 0.01)
      return fail("Gain " + std::to_string(options.gain) + " not accepted (camera has " + std::to_string(out->gain) + ")");
  }
  if (options.frame_rate_hz > 0) {
    arv_camera_set_frame_rate(camera, options.frame_rate_hz, &gerror);
    if (failed("AcquisitionFrameRate", &message)) return fail(message);
  }
  if (arv_camera_is_frame_rate_available(camera, nullptr)) {
    out->frame_rate_hz = arv_camera_get_frame_rate(camera, &gerror);
    if (failed("AcquisitionFrameRate read-back", &message)) return fail(message);
    if (options.frame_rate_hz > 0 && std::abs(out->frame_rate_hz - options.frame_rate_hz) > 0.01 * options.frame_rate_hz)
      return fail("AcquisitionFrameRate " + std::to_string(options.frame_rate_hz) + " Hz not accepted (camera has " +
                  std::to_string(out->frame_rate_hz) + " Hz)");
  }

  if (options.on_open) options.on_open(camera);

  session->stream = arv_camera_create_stream(camera, nullptr, nullptr, &gerror);
  if (failed("create stream", &message) || !session->stream) {
    return fail(message.empty() ? std::string("create stream failed") : message);
  }
  const guint payload = arv_camera_get_payload(camera, &gerror);
  if (failed("PayloadSize", &message)) return fail(message);
  session->payload_bytes = payload;
  for (int i = 0; i < std::max(options.buffer_count, 2); ++i)
    arv_stream_push_buffer(session->stream, arv_buffer_new_allocate(payload));

  control_lost.store(false);
  session->control_lost_handler =
      g_signal_connect(session->device, "control-lost", G_CALLBACK(aravisOnControlLost), &control_lost);

  arv_camera_start_acquisition(camera, &gerror);
  if (failed("AcquisitionStart", &message)) return fail(message);
  session->acquiring = true;
  return session;
}

std::chrono::milliseconds AravisCamera::Impl::lostTimeout() const {
  if (options.lost_timeout.count() > 0) return options.lost_timeout;
  std::lock_guard lock(mutex);
  const double period_ms = settings.frame_rate_hz > 0 ? 1000.0 / settings.frame_rate_hz : 0.0;
  return std::chrono::milliseconds(std::max<std::int64_t>(2000, std::llround(10 * period_ms)));
}

void AravisCamera::Impl::dropBuffer(const char* reason) {
  ++incomplete_since_good;
  ++drops_since_log;
  std::string summary;
  {
    std::lock_guard lock(mutex);
    ++details.stats.incomplete;
    ++details.dropped_by_reason[reason];
    for (const auto& [name, count] : details.dropped_by_reason)
      summary.append(summary.empty() ? "" : ", ").append(name).append(" ").append(std::to_string(count));
  }
  const std::int64_t now_ns = clock.nowNs();
  if (last_drop_log_ns == 0 || now_ns - last_drop_log_ns >= 1'000'000'000) {
    log(std::string("dropped an incomplete frame (") + reason + "); " + std::to_string(drops_since_log) +
        " since the last line; totals: " + summary);
    last_drop_log_ns = now_ns;
    drops_since_log = 0;
  }
}

void AravisCamera::Impl::processBuffer(ArvBuffer* buffer) {
  const ArvBufferStatus status = arv_buffer_get_status(buffer);
  if (status != ARV_BUFFER_STATUS_SUCCESS) return dropBuffer(aravisBufferStatusName(status));

  size_t size = 0;
  const auto* data = static_cast<const std::uint8_t*>(arv_buffer_get_image_data(buffer, &size));
  if (!data) return dropBuffer("NO_IMAGE");
  // Aravis reports no received size for a fake camera filled by a custom pattern (tests); the data
  // then lies within our allocation.
  if (size == 0) size = session->payload_bytes;
  const std::optional<PixelFormat> format = aravisToPixelFormat(arv_buffer_get_image_pixel_format(buffer));
  if (!format) return dropBuffer("UNSUPPORTED_FORMAT");
  const int width = arv_buffer_get_image_width(buffer);
  const int height = arv_buffer_get_image_height(buffer);
  gint padding_x = 0, padding_y = 0;
  arv_buffer_get_image_padding(buffer, &padding_x, &padding_y);
  const int row_bytes = width * bytesPerPixel(*format);
  const int stride = row_bytes + std::max(padding_x, 0);
  if (width < 2 || height < 2 ||
      size < static_cast<std::size_t>(stride) * static_cast<std::size_t>(height - 1) + static_cast<std::size_t>(row_bytes))
    return dropBuffer("SHORT_IMAGE");

  // Frame ids: gaps among complete frames, less the incomplete ones dropped in between.
  const FrameIdTracker::Step step = frame_ids.next(arv_buffer_get_frame_id(buffer));
  const std::uint64_t lost = step.lost > incomplete_since_good ? step.lost - incomplete_since_good : 0;
  incomplete_since_good = 0;

  // Host arrival: Aravis's system timestamp (realtime ns, taken when the frame arrived) moved onto
  // the steady clock; the pop time when there is none.
  const std::int64_t steady_now_ns = clock.nowNs();
  const std::int64_t real_now_ns = aravisRealtimeNs();
  const auto system_ns = static_cast<std::int64_t>(arv_buffer_get_system_timestamp(buffer));
  std::int64_t arrival_ns = steady_now_ns;
  if (system_ns > 0 && real_now_ns - system_ns >= 0 && real_now_ns - system_ns < 10'000'000'000)
    arrival_ns = steady_now_ns - (real_now_ns - system_ns);

  CameraFrame frame;
  const auto hw_ns = static_cast<std::int64_t>(arv_buffer_get_timestamp(buffer));
  std::int64_t earliest_arrival_ns = arrival_ns;
  if (hw_ns > 0) {
    mapping.add(hw_ns, arrival_ns);
    earliest_arrival_ns = mapping.toHostNs(hw_ns);
    frame.timestamp_from_hardware = true;
  }
  double exposure_us = 0;
  {
    std::lock_guard lock(mutex);
    exposure_us = settings.exposure_us;
  }
  frame.capture_ns = earliest_arrival_ns - options.readout_transfer_ns - std::llround(exposure_us * 500.0);
  frame.sequence = step.sequence;
  frame.exposure_us = static_cast<std::uint32_t>(std::lround(exposure_us));
  frame.width = width;
  frame.height = height;

  auto pixels = std::make_shared<std::vector<std::uint8_t>>();
  if (isBayer(*format) && options.debayer) {
    std::string error;
    if (!debayerBilinear(data, width, height, stride, *format, *pixels, &error)) return dropBuffer("DEBAYER_FAILED");
    frame.format = PixelFormat::kRgb8;
    frame.stride_bytes = width * 3;
  } else {
    pixels->resize(static_cast<std::size_t>(row_bytes) * height);
    for (int y = 0; y < height; ++y)
      std::copy_n(data + static_cast<std::ptrdiff_t>(y) * stride, row_bytes,
                  pixels->data() + static_cast<std::ptrdiff_t>(y) * row_bytes);
    frame.format = *format;
    frame.stride_bytes = row_bytes;
  }
  frame.pixels = std::move(pixels);

  {
    std::lock_guard lock(mutex);
    details.stats.lost += lost;
    details.clock_jumps = mapping.jumps();
    details.hw_to_host_offset_ns = mapping.valid() ? mapping.hwToHostOffsetNs() : 0;
    details.clock_drift_ppm = mapping.driftPpm();
    details.clock_pairs = mapping.size();
    while (static_cast<int>(queue.size()) >= std::max(options.queue_depth, 1)) {
      queue.pop_front();
      ++details.queue_overflows;
    }
    queue.push_back(std::move(frame));
  }
  frame_ready.notify_one();
}

void AravisCamera::Impl::loseCamera(const std::string& reason) {
  log("camera lost (" + reason + "); closing it and re-opening");
  session.reset();
  mapping.reset();
  frame_ids.reset();
  incomplete_since_good = 0;
  std::lock_guard lock(mutex);
  details.stats.last_error = "camera lost: " + reason;
}

bool AravisCamera::Impl::reopen() {
  std::chrono::milliseconds backoff = options.reconnect_backoff_min;
  std::uint64_t attempts = 0;
  while (!stop_requested.load()) {
    {
      std::unique_lock lock(mutex);
      wake.wait_for(lock, backoff, [&] { return stop_requested.load(); });
    }
    if (stop_requested.load()) return false;
    ++attempts;
    AravisCameraSettings reopened;
    std::string error;
    std::unique_ptr<AravisSession> s = open(&reopened, &error);
    {
      std::lock_guard lock(mutex);
      ++details.reconnect_attempts;
      if (s) {
        ++details.stats.reconnects;
        details.stats.last_error.clear();
        settings = reopened;
      } else {
        details.stats.last_error = "camera lost; re-open failed: " + error;
      }
    }
    if (s) {
      session = std::move(s);
      last_buffer_ns = clock.nowNs();
      log("re-opened after " + std::to_string(attempts) + " attempt(s)");
      return true;
    }
    if (attempts == 1 || (attempts & (attempts - 1)) == 0) log("re-open attempt " + std::to_string(attempts) + " failed: " + error);
    backoff = std::min(backoff * 2, options.reconnect_backoff_max);
  }
  return false;
}

void AravisCamera::Impl::streamLoop() {
  last_buffer_ns = clock.nowNs();
  while (!stop_requested.load()) {
    if (!session) {
      reopen();
      continue;
    }
    ArvBuffer* buffer = arv_stream_timeout_pop_buffer(session->stream, 100'000);
    if (control_lost.load()) {
      if (buffer) arv_stream_push_buffer(session->stream, buffer);
      loseCamera("control lost");
      continue;
    }
    if (!buffer) {
      const std::int64_t silent_ns = clock.nowNs() - last_buffer_ns;
      if (silent_ns > std::chrono::nanoseconds(lostTimeout()).count())
        loseCamera("no buffer for " + std::to_string(silent_ns / 1'000'000) + " ms");
      continue;
    }
    last_buffer_ns = clock.nowNs();
    processBuffer(buffer);
    arv_stream_push_buffer(session->stream, buffer);
  }
}

AravisCamera::AravisCamera(AravisCameraOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}

AravisCamera::~AravisCamera() { stop(); }

std::string AravisCamera::name() const { return impl_->label(); }

bool AravisCamera::start(std::string* error) {
  Impl& d = *impl_;
  {
    std::lock_guard lock(d.mutex);
    if (d.running) return true;
    d.details = {};
    d.queue.clear();
  }
  d.mapping.reset();
  d.frame_ids = FrameIdTracker();
  d.incomplete_since_good = 0;
  d.last_drop_log_ns = 0;
  d.drops_since_log = 0;

  AravisCameraSettings opened;
  std::string message;
  std::unique_ptr<AravisSession> session = d.open(&opened, &message);
  if (!session) {
    std::lock_guard lock(d.mutex);
    d.details.stats.last_error = message;
    if (error) *error = message;
    return false;
  }
  d.session = std::move(session);
  {
    std::lock_guard lock(d.mutex);
    d.settings = opened;
    d.running = true;
  }
  d.stop_requested.store(false);
  d.thread = std::thread([&d] { d.streamLoop(); });
  return true;
}

void AravisCamera::stop() {
  Impl& d = *impl_;
  {
    std::lock_guard lock(d.mutex);
    if (!d.running) return;
    d.stop_requested.store(true);
  }
  d.wake.notify_all();
  if (d.thread.joinable()) d.thread.join();
  d.session.reset();
  {
    std::lock_guard lock(d.mutex);
    d.running = false;
    d.queue.clear();
  }
  d.frame_ready.notify_all();
}

std::optional<CameraFrame> AravisCamera::nextFrame(std::chrono::milliseconds timeout) {
  Impl& d = *impl_;
  std::unique_lock lock(d.mutex);
  d.frame_ready.wait_for(lock, timeout, [&] { return !d.running || !d.queue.empty(); });
  if (!d.running || d.queue.empty()) return std::nullopt;
  CameraFrame frame = std::move(d.queue.front());
  d.queue.pop_front();
  ++d.details.stats.frames;
  return frame;
}

CameraStats AravisCamera::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->details.stats;
}

AravisCameraDetails AravisCamera::details() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->details;
}

AravisCameraSettings AravisCamera::settings() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->settings;
}

void AravisCamera::enableFakeInterface() {
  std::lock_guard lock(aravisSystemMutex());
  arv_enable_interface("Fake");
}

std::vector<std::string> AravisCamera::listDevices() {
  std::lock_guard lock(aravisSystemMutex());
  std::vector<std::string> out;
  for (const AravisDeviceInfo& d : aravisScanDevices()) out.push_back(d.describe());
  return out;
}

}  // namespace telesphere::robot
