// SPDX-License-Identifier: MIT
/// @brief AravisCamera's stream thread: each buffer dropped with its reason or turned into a CameraFrame
///        (frame id → sequence, hardware stamp → our clock, wide samples → 8 bits, debayer), the camera lost and re-opened.
#include "robot/cameras/aravis_camera_impl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace telesphere::robot::cameras {

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
  const std::optional<AravisLayout> layout = aravisLayoutOf(arv_buffer_get_image_pixel_format(buffer));
  if (!layout) return dropBuffer("UNSUPPORTED_FORMAT");
  const PixelFormat format = layout->format;
  const int width = arv_buffer_get_image_width(buffer);
  const int height = arv_buffer_get_image_height(buffer);
  gint padding_x = 0, padding_y = 0;
  arv_buffer_get_image_padding(buffer, &padding_x, &padding_y);
  const int wire_row_bytes = width * layout->bytesPerPixel();
  const int wire_stride = wire_row_bytes + std::max(padding_x, 0);
  if (width < 2 || height < 2 ||
      size < static_cast<std::size_t>(wire_stride) * static_cast<std::size_t>(height - 1) + static_cast<std::size_t>(wire_row_bytes))
    return dropBuffer("SHORT_IMAGE");
  const int row_bytes = width * bytesPerPixel(format);  // at 8 bits per sample

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

  auto pixels = frame_buffers.acquire();
  const bool debayer = isBayer(format) && options.debayer;
  if (layout->sample_bits > 8) {
    // A wide sensor: its samples at 8 bits, into the frame itself or, before a debayer, into a
    // buffer kept from frame to frame.
    std::vector<std::uint8_t>& into = debayer ? narrowed : *pixels;
    into.resize(static_cast<std::size_t>(row_bytes) * height);
    if (!narrowSamplesTo8Bits(data, width, height, wire_stride, layout->sample_bits, into.data(), row_bytes, nullptr))
      return dropBuffer("NARROW_FAILED");
    data = into.data();
  }
  const int stride = layout->sample_bits > 8 ? row_bytes : wire_stride;
  if (debayer) {
    std::string error;
    if (!debayerBilinear(data, width, height, stride, format, *pixels, &error)) return dropBuffer("DEBAYER_FAILED");
    frame.format = PixelFormat::kRgb8;
    frame.stride_bytes = width * 3;
  } else {
    if (layout->sample_bits == 8) {
      pixels->resize(static_cast<std::size_t>(row_bytes) * height);
      for (int y = 0; y < height; ++y)
        std::copy_n(data + static_cast<std::ptrdiff_t>(y) * stride, row_bytes,
                    pixels->data() + static_cast<std::ptrdiff_t>(y) * row_bytes);
    }
    frame.format = format;
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

}  // namespace telesphere::robot::cameras
