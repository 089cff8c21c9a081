// SPDX-License-Identifier: MIT
/// @brief CalibrationRobot (see calibration_robot.h).
#include "console/calibration/calibration_robot.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <thread>

#include "calib/system_calibration_yaml.h"
#include "robot/link/link_pose.h"

namespace telesphere::console::calibration {
namespace {

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

}  // namespace

CalibrationRobot::CalibrationRobot(link::LinkClient& client, const std::string& holder,
                                   std::chrono::milliseconds request_timeout)
    : client_(client), request_timeout_(request_timeout) {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "?");
  holder_ = holder + ", pid " + std::to_string(getpid()) + " on " + host;
}

CalibrationRobot::~CalibrationRobot() {
  bool holding = false;
  {
    std::lock_guard lock(mutex_);
    holding = lease_ != 0;
  }
  if (holding) {
    std::string ignored;
    release(&ignored);
  }
  stopRenewals();
}

std::string CalibrationRobot::holdLost() const {
  std::lock_guard lock(mutex_);
  return lost_;
}

std::optional<link::proto::ControlReply> CalibrationRobot::request(link::proto::ControlRequest r, std::string* error,
                                                                   std::optional<std::chrono::milliseconds> timeout) {
  const std::chrono::milliseconds wait = timeout.value_or(request_timeout_);
  auto reply = client_.request(std::move(r), wait);
  if (!reply) {
    *error = "the robot did not answer within " + std::to_string(wait.count()) + " ms";
    return std::nullopt;
  }
  if (!reply->ok()) {
    *error = reply->error();
    return std::nullopt;
  }
  return reply;
}

bool CalibrationRobot::hold(link::proto::ControlRequest r, std::string* error) {
  {
    std::lock_guard lock(mutex_);
    if (!lost_.empty()) {  // the supervisor (or the lease) ended it: never grab the head again unasked
      *error = "the robot no longer holds the head for this calibration: " + lost_;
      return false;
    }
    r.mutable_calibration_head_pose()->set_lease(lease_);
    r.mutable_calibration_head_pose()->set_holder(holder_);
  }
  const auto reply = request(std::move(r), error);
  if (!reply) return false;
  std::lock_guard lock(mutex_);
  lease_ = reply->hold().lease();
  stopping_ = false;
  if (!renewer_.joinable()) renewer_ = std::thread([this] { renewals(); });
  return true;
}

void CalibrationRobot::renewals() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, kRenewPeriod, [&] { return stopping_; });
    if (stopping_ || lease_ == 0) continue;
    link::proto::ControlRequest r;
    r.mutable_calibration_head_pose()->set_renew(true);
    r.mutable_calibration_head_pose()->set_lease(lease_);
    const std::uint64_t lease = lease_;
    lock.unlock();
    // No answer: try again (the robot releases the head by itself if it never hears us).
    const auto reply = client_.request(std::move(r), kRenewPeriod * 2);
    lock.lock();
    if (reply && !reply->ok() && lease_ == lease) {
      lost_ = reply->error();
      lease_ = 0;
    }
  }
}

void CalibrationRobot::stopRenewals() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (renewer_.joinable()) renewer_.join();
}

bool CalibrationRobot::holdHeadAt(const Eigen::Isometry3d& T_robot_head, std::string* error) {
  link::proto::ControlRequest r;
  link::toLinkPose(T_robot_head, r.mutable_calibration_head_pose()->mutable_t_robot_head());
  return hold(std::move(r), error);
}

bool CalibrationRobot::runHeadPattern(double amplitude_deg, std::string* error) {
  link::proto::ControlRequest r;
  r.mutable_calibration_head_pose()->set_pattern_amplitude_deg(amplitude_deg);
  return hold(std::move(r), error);
}

bool CalibrationRobot::returnHeadTo(const Eigen::Isometry3d& T_robot_head, const SettleOptions& options,
                                    std::string* error) {
  return holdHeadAt(T_robot_head, error) && waitSettled(T_robot_head, options, nullptr, error);
}

bool CalibrationRobot::release(std::string* error) {
  link::proto::ControlRequest r;
  r.mutable_calibration_head_pose()->set_release(true);
  r.mutable_calibration_head_pose()->set_holder(holder_);
  {
    std::lock_guard lock(mutex_);
    if (lease_ == 0) return true;  // nothing held (or the robot ended it already)
    r.mutable_calibration_head_pose()->set_lease(lease_);
  }
  const bool ok = request(std::move(r), error).has_value();
  {
    std::lock_guard lock(mutex_);
    if (ok) lease_ = 0;
  }
  if (ok) stopRenewals();
  return ok;
}

std::optional<link::proto::CalibrationInUse> CalibrationRobot::calibrationRequest(link::proto::ControlRequest r,
                                                                                 std::string* error) {
  const auto reply = request(std::move(r), error);
  if (!reply) return std::nullopt;
  return reply->calibration();
}

std::optional<link::proto::CalibrationInUse> CalibrationRobot::calibrationInUse(std::string* error) {
  link::proto::ControlRequest r;
  r.set_get_calibration(true);
  return calibrationRequest(std::move(r), error);
}

std::optional<link::proto::CalibrationInUse> CalibrationRobot::applyCalibration(
    const calib::SystemCalibration& calibration, const std::string& source, std::string* error) {
  if (const auto problem = calibration.inconsistency()) {
    *error = "not applied: " + problem->first + ": " + problem->second;
    return std::nullopt;
  }
  link::proto::ControlRequest r;
  r.mutable_apply_calibration()->set_text(calib::toSystemCalibrationYaml(calibration));
  r.mutable_apply_calibration()->set_source(source);
  return calibrationRequest(std::move(r), error);
}

std::optional<link::proto::CalibrationInUse> CalibrationRobot::revertCalibration(std::string* error) {
  link::proto::ControlRequest r;
  r.set_revert_calibration(true);
  return calibrationRequest(std::move(r), error);
}

bool CalibrationRobot::waitSettled(const Eigen::Isometry3d& T_robot_head, const SettleOptions& options,
                                   const std::atomic<bool>* cancel, std::string* error) {
  const auto deadline = std::chrono::steady_clock::now() + options.timeout;
  std::int64_t last_t_ns = 0;
  std::optional<Eigen::Isometry3d> previous;
  int still = 0;
  double dp = NAN, da = NAN;
  while (std::chrono::steady_clock::now() < deadline) {
    if (cancel != nullptr && cancel->load()) {
      *error = "cancelled";
      return false;
    }
    if (const std::string lost = holdLost(); !lost.empty()) {
      *error = "the robot no longer holds the head for this calibration: " + lost;
      return false;
    }
    const auto state = client_.latestRobotState();
    if (state && state->t_ns() != last_t_ns && state->has_t_robot_head()) {
      last_t_ns = state->t_ns();
      const Eigen::Isometry3d T = link::fromLinkPose(state->t_robot_head());
      dp = (T.translation() - T_robot_head.translation()).norm();
      da = angleDeg(T.linear(), T_robot_head.linear());
      const bool there = dp <= options.position_tolerance_m && da <= options.angle_tolerance_deg;
      const bool unmoved = previous && (T.translation() - previous->translation()).norm() <= options.still_position_m &&
                           angleDeg(T.linear(), previous->linear()) <= options.still_angle_deg;
      still = there && unmoved ? still + 1 : 0;
      previous = T;
      if (!state->arm_ok()) {
        *error = "the arm stopped: " + state->fault();
        return false;
      }
      if (still >= options.still_states) return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  char buf[200];
  std::snprintf(buf, sizeof buf, "the head did not settle within %.1f s (%.1f mm and %.2f° from the pose asked for)",
                double(options.timeout.count()) / 1000.0, dp * 1000.0, da);
  *error = buf;
  return false;
}

std::optional<link::proto::CalibrationStill> CalibrationRobot::takeStill(std::string* error) {
  link::proto::ControlRequest r;
  r.set_calibration_capture(true);
  auto reply = request(std::move(r), error, still_timeout_);
  if (!reply) return std::nullopt;
  if (!reply->has_still()) {
    *error = "the robot's reply holds no still";
    return std::nullopt;
  }
  return std::move(*reply->mutable_still());
}

std::optional<Eigen::Isometry3d> CalibrationRobot::headPose(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  do {
    if (const auto state = client_.latestRobotState(); state && state->has_t_robot_head()) {
      return link::fromLinkPose(state->t_robot_head());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  } while (std::chrono::steady_clock::now() < deadline);
  return std::nullopt;
}

}  // namespace telesphere::console::calibration
