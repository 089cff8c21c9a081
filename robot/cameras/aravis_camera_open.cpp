// SPDX-License-Identifier: MIT
/// @brief AravisCamera::Impl::open: find the camera, configure it (pixel format, size, rate, exposure,
///        gain, packet size, timestamps) and read back what it uses; the buffer pool.
#include "robot/cameras/aravis_camera_impl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace telesphere::robot::cameras {

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
    std::vector<std::string> offered;
    for (guint i = 0; i < n; ++i) {
      list.append(i ? ", " : "").append(available[i]);
      offered.emplace_back(available[i]);
    }
    g_free(available);
    // The 8-bit layout asked for, else the narrowest wider form of it (narrowed at capture): a
    // sensor that streams only 12 bits still gives the video path its 8.
    const AravisLayout* chosen = nullptr;
    for (const AravisLayout& layout : kAravisLayouts)
      if (!chosen && layout.format == *options.pixel_format &&
          std::find(offered.begin(), offered.end(), layout.name) != offered.end())
        chosen = &layout;
    if (!chosen) return fail(std::string("PixelFormat ") + wanted_format + " not offered (nor a 10-16-bit form of it); the camera has: " + list);
    if (chosen->sample_bits > 8)
      log(std::string("PixelFormat ") + wanted_format + " not offered: using " + chosen->name + ", narrowed to 8 bits at capture");
    arv_camera_set_pixel_format(camera, chosen->arv, &gerror);
    if (failed("PixelFormat", &message)) return fail(message);
  }
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

  // Read back after on_open, which may set features of its own (a test's PixelFormat).
  const ArvPixelFormat camera_format = arv_camera_get_pixel_format(camera, &gerror);
  if (failed("PixelFormat read-back", &message)) return fail(message);
  const std::optional<AravisLayout> layout = aravisLayoutOf(camera_format);
  if (!layout) {
    const char* name = arv_camera_get_pixel_format_as_string(camera, nullptr);
    return fail(std::string("camera PixelFormat ") + (name ? name : "?") + " is not one of " + kAravisLayoutsAccepted +
                "; set options.pixel_format");
  }
  out->camera_format = layout->format;
  out->camera_sample_bits = layout->sample_bits;
  out->output_format = (isBayer(layout->format) && options.debayer) ? PixelFormat::kRgb8 : layout->format;

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

}  // namespace telesphere::robot::cameras
