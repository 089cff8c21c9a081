// SPDX-License-Identifier: MIT
/// @brief AravisCamera: a GenICam camera (GigE Vision, USB3 Vision, Aravis's fake camera) through
///        Aravis 0.8 as a CameraSource: configured at start, streamed through a buffer pool on
///        its own thread, 10–16-bit samples narrowed to 8, Bayer debayered to RGB8 (or passed on
///        raw), hardware timestamps mapped to the host clock,
///        incomplete and lost frames counted, re-opened when the camera disappears.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot/clock/device_clock_mapping.h"
#include "robot/cameras/camera_source.h"

namespace telesphere::robot::cameras {

struct AravisCameraOptions {
  /// Which camera: its Aravis device id ("Fake_1", "Basler-21234567"), physical id, address or
  /// serial number; empty = the first one found.
  std::string device_id;
  int width = 0;   ///< px; 0 keeps the camera's
  int height = 0;  ///< px; 0 keeps the camera's
  /// PixelFormat to set; where the camera does not offer it, the narrowest of its 10/12/14/16-bit
  /// unpacked forms it offers (BayerRG12 for BayerRG8), narrowed to 8 bits at capture. nullopt keeps
  /// the camera's, which must be one of PixelFormat's or such a wider form.
  std::optional<PixelFormat> pixel_format;
  double frame_rate_hz = 0;  ///< AcquisitionFrameRate; 0 keeps the camera's
  double exposure_us = 0;    ///< fixed ExposureTime (ExposureAuto off); 0 keeps the camera's
  double gain = -1;          ///< fixed Gain (GainAuto off), the camera's unit (dB mostly); < 0 keeps it
  int buffer_count = 8;      ///< buffers in the stream's pool
  bool debayer = true;       ///< Bayer frames → RGB8 (false: delivered as the raw mosaic)
  int queue_depth = 2;       ///< frames waiting for nextFrame(); when full the oldest is dropped
  /// Minimum time from the end of the exposure to the buffer's arrival on the host (sensor readout
  /// plus transfer), ns: the part of the mapped arrival delay that is not the exposure. Measure it
  /// once per camera and link (e.g. an LED toggled on a known host time); 0 by default.
  std::int64_t readout_transfer_ns = 0;
  /// No buffer for this long counts as the camera being gone (re-open); 0 = max(2 s, 10 frames).
  std::chrono::milliseconds lost_timeout{0};
  std::chrono::milliseconds reconnect_backoff_min{100};  ///< first re-open retry delay, doubling
  std::chrono::milliseconds reconnect_backoff_max{2000};
  clock::DeviceClockMappingOptions clock;
  /// Called with the ArvCamera* after each open and configuration, before acquisition starts (on
  /// the thread that opens: start()'s caller, later the stream thread). For features this class
  /// does not set, and for tests (the fake camera's fill pattern); the PixelFormat is read back
  /// after it. Must not keep the pointer
  /// beyond the camera's life without taking a GObject reference.
  std::function<void(void* arv_camera)> on_open;
};

/// What the camera actually runs with (read back after configuring).
struct AravisCameraSettings {
  std::string device_id;      ///< Aravis device id of the opened camera
  std::string serial_number;
  std::string model;
  int width = 0;
  int height = 0;
  PixelFormat camera_format = PixelFormat::kMono8;  ///< as the camera sends it (its layout at 8 bits)
  int camera_sample_bits = 8;  ///< bits per sample on the wire: 8, or 10–16 narrowed to 8 at capture
  PixelFormat output_format = PixelFormat::kMono8;  ///< as frames are delivered
  double frame_rate_hz = 0;
  double exposure_us = 0;
  double gain = 0;
};

/// Counters beyond CameraStats, and the clock mapping's current estimate.
struct AravisCameraDetails {
  CameraStats stats;
  std::map<std::string, std::uint64_t> dropped_by_reason;  ///< "MISSING_PACKETS", "SIZE_MISMATCH", …
  std::uint64_t queue_overflows = 0;      ///< frames dropped because nextFrame() fell behind
  std::uint64_t reconnect_attempts = 0;   ///< re-opens tried (failed ones included)
  std::uint64_t clock_jumps = 0;          ///< resets of the clock mapping by a hardware clock jump
  std::int64_t hw_to_host_offset_ns = 0;  ///< t_host − t_hw at the newest frame (incl. min delay)
  double clock_drift_ppm = 0;             ///< (b − 1)·10⁶ of t_host = a + b·t_hw
  std::size_t clock_pairs = 0;            ///< pairs in the mapping's window
};

/// A GenICam camera through Aravis. Thread model: one stream thread per camera pops buffers,
/// converts and queues frames; nextFrame() may be called from one consumer thread; stats(),
/// details() and settings() from any. start()/stop() from one controlling thread.
///
/// Per buffer: status ≠ SUCCESS (missing packets, size mismatch, aborted, …) → dropped, counted
/// in `incomplete` and by reason, a log line to stderr (at most one a second); gaps in the frame
/// ids of the complete frames, less the incomplete ones in between, → `lost` (FrameIdTracker).
/// capture_ns (host steady ns, middle of the exposure) = earliest arrival mapped from the hardware
/// stamp (DeviceClockMapping) − readout_transfer_ns − exposure/2; cameras without hardware
/// stamps use the host arrival instead (timestamp_from_hardware = false).
/// Camera loss (the device's "control-lost" signal, or no buffer for lost_timeout) → the camera is
/// closed, `last_error` set, a line logged, and re-opened with exponential backoff until it is
/// back (`reconnects` counts successes); the clock mapping and frame ids then start afresh.
class AravisCamera final : public CameraSource {
 public:
  explicit AravisCamera(AravisCameraOptions options);
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  std::string name() const override;
  /// Opens and configures the camera, starts acquisition and the stream thread. On failure the
  /// error names the device and what went wrong; a missing device lists the devices found.
  bool start(std::string* error) override;
  void stop() override;
  std::optional<CameraFrame> nextFrame(std::chrono::milliseconds timeout) override;
  CameraStats stats() const override;

  AravisCameraDetails details() const;
  /// Valid after a successful start().
  AravisCameraSettings settings() const;

  /// Makes Aravis's in-process fake camera ("Fake_1") discoverable (off by default in Aravis).
  static void enableFakeInterface();
  /// "Fake_1 (Aravis Fake, serial 1, Fake)" for every device Aravis finds now.
  static std::vector<std::string> listDevices();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::robot::cameras
