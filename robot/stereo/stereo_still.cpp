// SPDX-License-Identifier: MIT
/// @brief StereoStillTaker (see stereo_still.h).
#include "robot/stereo/stereo_still.h"

#include <algorithm>
#include <vector>

#include "robot/cameras/debayer.h"
#include "robot/link/link_pose.h"

namespace telesphere::robot::stereo {

bool toGray8(const cameras::CameraFrame& frame, std::string* gray, std::string* error) {
  if (!frame.pixels || frame.width <= 0 || frame.height <= 0 ||
      frame.stride_bytes < frame.width * cameras::bytesPerPixel(frame.format) ||
      frame.pixels->size() < std::size_t(frame.stride_bytes) * std::size_t(frame.height - 1) +
                                 std::size_t(frame.width * cameras::bytesPerPixel(frame.format))) {
    *error = "camera frame without valid pixels";
    return false;
  }
  const std::size_t w = std::size_t(frame.width), h = std::size_t(frame.height);
  gray->resize(w * h);
  const std::uint8_t* src = frame.pixels->data();
  const auto luma = [](int r, int g, int b) { return char((299 * r + 587 * g + 114 * b + 500) / 1000); };
  if (frame.format == cameras::PixelFormat::kMono8) {
    for (std::size_t y = 0; y < h; ++y)
      std::copy_n(src + y * std::size_t(frame.stride_bytes), w, gray->begin() + std::ptrdiff_t(y * w));
    return true;
  }
  if (frame.format == cameras::PixelFormat::kRgb8) {
    for (std::size_t y = 0; y < h; ++y) {
      const std::uint8_t* row = src + y * std::size_t(frame.stride_bytes);
      for (std::size_t x = 0; x < w; ++x) (*gray)[y * w + x] = luma(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
    }
    return true;
  }
  std::vector<std::uint8_t> rgb;
  if (!cameras::debayerBilinear(src, frame.width, frame.height, frame.stride_bytes, frame.format, rgb, error)) return false;
  for (std::size_t i = 0; i < w * h; ++i) (*gray)[i] = luma(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
  return true;
}

void StereoStillTaker::offer(const StereoFrame& pair, std::uint64_t sequence) {
  {
    std::lock_guard lock(mutex_);
    newest_.emplace(pair, sequence);
  }
  offered_.notify_all();
}

std::uint64_t StereoStillTaker::taken() const {
  std::lock_guard lock(mutex_);
  return taken_;
}

bool StereoStillTaker::take(link::proto::CalibrationStill* still, std::chrono::milliseconds timeout,
                            std::string* error) {
  const std::int64_t requested_ns = clock_.nowNs();
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::optional<std::pair<StereoFrame, std::uint64_t>> pair;
  {
    std::unique_lock lock(mutex_);
    ++takers_waiting_;
    const bool got = offered_.wait_until(lock, deadline, [&] {
      return newest_ && std::min(newest_->first.left.capture_ns, newest_->first.right.capture_ns) > requested_ns;
    });
    --takers_waiting_;
    if (!got) {
      *error = "no stereo frame captured within " + std::to_string(timeout.count()) +
               " ms of the request (are both cameras delivering?)";
      return false;
    }
    pair = newest_;
  }
  const StereoFrame& frame = pair->first;
  const std::int64_t capture_ns = frame.left.capture_ns;
  // Joint states on both sides of the capture time: wait for the one after (the arms report at
  // their own rate), never extrapolate.
  const std::int64_t first_capture_ns = std::min(capture_ns, frame.right.capture_ns);
  const std::int64_t last_capture_ns = std::max(capture_ns, frame.right.capture_ns);
  const auto bracketed = [&](const head::JointStateBuffer& buffer, const char* arm) {
    buffer.waitForSampleAtOrAfter(last_capture_ns, deadline);  // woken by each state it reports
    const auto window = buffer.window();
    if (window && window->first <= first_capture_ns && window->second >= last_capture_ns) return true;
    if (window && window->first > first_capture_ns)
      *error = std::string("the ") + arm + "'s joint states of the capture time are no longer kept";
    else
      *error = window ? std::string("no joint state of the ") + arm + " after the capture time arrived in time (is it reporting?)"
                      : std::string("no joint states at all from the ") + arm + " (is it connected?)";
    return false;
  };
  if (!bracketed(joints_, "head arm")) return false;
  if (manipulator_ != nullptr && !bracketed(*manipulator_, "manipulator")) return false;
  const auto q = joints_.jointsAt(capture_ns);
  const auto T_l = joints_.T_robot_cam(cameras::CameraSide::kLeft, frame.left.capture_ns);
  const auto T_r = joints_.T_robot_cam(cameras::CameraSide::kRight, frame.right.capture_ns);
  if (!q || !T_l || !T_r) {
    *error = "no joint state at the capture time";
    return false;
  }
  still->Clear();
  still->set_sequence(pair->second);
  still->set_capture_ns(capture_ns);
  for (int i = 0; i < q->size(); ++i) still->add_head_joints((*q)[i]);
  // The bracketing states themselves, for the console's freshness check.
  const auto bracket = joints_.bracket(capture_ns);
  if (!bracket) {
    *error = "the joint states of the capture time are no longer kept";
    return false;
  }
  still->set_joints_before_ns(bracket->first);
  still->set_joints_after_ns(bracket->second);
  if (const auto T_robot_flange = joints_.T_robot_flange(capture_ns))
    link::toLinkPose(*T_robot_flange, still->mutable_t_robot_flange());
  if (manipulator_ != nullptr) {
    const auto q_m = manipulator_->jointsAt(capture_ns);
    const auto T_mount_wrist = manipulator_->T_robot_flange(capture_ns);
    const auto bracket_m = manipulator_->bracket(capture_ns);
    if (!q_m || !T_mount_wrist || !bracket_m) {
      *error = "no manipulator joint state at the capture time";
      return false;
    }
    for (int i = 0; i < q_m->size(); ++i) still->add_manipulator_joints((*q_m)[i]);
    still->set_manipulator_before_ns(bracket_m->first);
    still->set_manipulator_after_ns(bracket_m->second);
    link::toLinkPose(*T_mount_wrist, still->mutable_t_mount_wrist());
  }
  const auto fill = [&](const cameras::CameraFrame& f, const Eigen::Isometry3d& T, link::proto::CalibrationImage* image) {
    image->set_width(std::uint32_t(f.width));
    image->set_height(std::uint32_t(f.height));
    image->set_capture_ns(f.capture_ns);
    link::toLinkPose(T, image->mutable_t_robot_cam());
    return toGray8(f, image->mutable_gray8(), error);
  };
  if (!fill(frame.left, *T_l, still->mutable_left()) || !fill(frame.right, *T_r, still->mutable_right())) return false;
  std::lock_guard lock(mutex_);
  ++taken_;
  return true;
}

}  // namespace telesphere::robot::stereo
