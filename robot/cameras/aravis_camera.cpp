// SPDX-License-Identifier: MIT
/// @brief AravisCamera's public calls: start, stop, frames, counters, settings, device list.
///        The session and its opening: aravis_camera_open.cpp; the stream thread: aravis_camera_stream.cpp.
#include "robot/cameras/aravis_camera.h"
#include "robot/cameras/aravis_camera_impl.h"

#include <mutex>

namespace telesphere::robot::cameras {

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

}  // namespace telesphere::robot::cameras
