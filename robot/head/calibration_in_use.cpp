// SPDX-License-Identifier: MIT
/// @brief CalibrationInUse: merge, checks, generations, revert, the link's requests.
#include "robot/head/calibration_in_use.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "calib/calibration_file.h"
#include "calib/system_calibration_yaml.h"

namespace telesphere::robot::head {

namespace {

HeadGeometry geometryOf(const calib::SystemCalibration& calibration) {
  HeadGeometry geometry;
  geometry.T_flange_cam_l = *calibration.T_flange_cam_l;
  geometry.T_cam_l_cam_r = *calibration.T_cam_l_cam_r;
  return geometry;
}

double aspect(const calib::CameraCalibration& camera) { return double(camera.width) / double(camera.height); }

}  // namespace

CalibrationInUse::CalibrationInUse(const calib::SystemCalibration& startup, std::string source, const clock::Clock& clock)
    : clock_(clock) {
  if (const auto why = unusable(startup)) throw std::invalid_argument("start-up calibration: " + *why);
  AppliedCalibration first;
  first.generation = 1;
  first.calibration = startup;
  first.geometry = geometryOf(startup);
  first.source = std::move(source);
  first.applied_ns = clock_.nowNs();
  current_ = std::make_shared<const AppliedCalibration>(std::move(first));
}

std::optional<std::string> CalibrationInUse::unusable(const calib::SystemCalibration& calibration) {
  if (const auto problem = calibration.inconsistency()) return problem->first + ": " + problem->second;
  if (calibration.cameras.size() != 2)
    return "needs two cameras (has " + std::to_string(calibration.cameras.size()) + ")";
  if (!calibration.T_cam_l_cam_r) return "needs T_cam_l_cam_r";
  if (!calibration.T_flange_cam_l) return "needs T_flange_cam_l (hand-eye)";
  return std::nullopt;
}

std::shared_ptr<const AppliedCalibration> CalibrationInUse::current() const {
  std::lock_guard lock(mutex_);
  return current_;
}

std::size_t CalibrationInUse::previousCount() const {
  std::lock_guard lock(mutex_);
  return previous_.size();
}

bool CalibrationInUse::apply(const calib::SystemCalibration& applied, std::string source, std::string* error) {
  std::lock_guard lock(mutex_);
  calib::SystemCalibration merged = applied;
  const calib::SystemCalibration& in_use = current_->calibration;
  if (merged.cameras.empty()) {
    merged.cameras = in_use.cameras;
    if (!merged.T_cam_l_cam_r) merged.T_cam_l_cam_r = in_use.T_cam_l_cam_r;
  }
  if (!merged.T_flange_cam_l) merged.T_flange_cam_l = in_use.T_flange_cam_l;
  if (!merged.T_robot_mount) merged.T_robot_mount = in_use.T_robot_mount;
  if (!merged.T_wrist_marker) merged.T_wrist_marker = in_use.T_wrist_marker;
  if (const auto why = unusable(merged)) {
    *error = "calibration not applied: " + *why;
    return false;
  }
  for (std::size_t i = 0; i < 2; ++i) {
    const double a_new = aspect(merged.cameras[i]), a_now = aspect(in_use.cameras[i]);
    if (std::abs(a_new - a_now) > 0.01 * a_now) {
      *error = "calibration not applied: camera " + merged.cameras[i].label + " is calibrated at " +
               std::to_string(merged.cameras[i].width) + "x" + std::to_string(merged.cameras[i].height) +
               ", another aspect ratio than the cameras in use (" + std::to_string(in_use.cameras[i].width) + "x" +
               std::to_string(in_use.cameras[i].height) + "): not these cameras";
      return false;
    }
  }
  previous_.push_back(current_);
  if (previous_.size() > kMaxPrevious) previous_.erase(previous_.begin());
  AppliedCalibration next;
  next.calibration = std::move(merged);
  next.geometry = geometryOf(next.calibration);
  next.source = source.empty() ? "applied from the link" : std::move(source);
  install(std::move(next));
  return true;
}

bool CalibrationInUse::revert(std::string* error) {
  std::lock_guard lock(mutex_);
  if (previous_.empty()) {
    *error = "no earlier calibration to go back to (generation " + std::to_string(current_->generation) +
             " is the one the robot started with or the oldest kept)";
    return false;
  }
  AppliedCalibration back = *previous_.back();
  previous_.pop_back();
  back.source = "reverted to generation " + std::to_string(back.generation) + ": " + back.source;
  install(std::move(back));
  return true;
}

void CalibrationInUse::setSavePath(std::string path) {
  std::lock_guard lock(mutex_);
  save_path_ = std::move(path);
}

void CalibrationInUse::install(AppliedCalibration next) {
  next.generation = next_generation_++;
  next.applied_ns = clock_.nowNs();
  current_ = std::make_shared<const AppliedCalibration>(std::move(next));
  saved_to_.clear();
  save_error_.clear();
  if (save_path_.empty()) return;
  // Whole or not at all: a temporary file beside it, renamed over it.
  const std::string temporary = save_path_ + ".saving";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << "# saved by telesphere-robot: calibration generation " << current_->generation << " (" << current_->source
        << ")\n"
        << calib::toSystemCalibrationYaml(current_->calibration);
    out.flush();
    if (!out) save_error_ = "cannot write " + temporary;
  }
  if (save_error_.empty() && std::rename(temporary.c_str(), save_path_.c_str()) != 0)
    save_error_ = "cannot rename " + temporary + " to " + save_path_ + ": " + std::strerror(errno);
  if (save_error_.empty()) {
    saved_to_ = save_path_;
  } else {
    std::remove(temporary.c_str());
    std::cerr << "telesphere-robot: the calibration in use was not saved: " << save_error_ << '\n';
  }
}

void CalibrationInUse::fill(link::proto::CalibrationInUse* out) const {
  std::shared_ptr<const AppliedCalibration> now;
  std::shared_ptr<const AppliedCalibration> before;
  std::size_t count = 0;
  {
    std::lock_guard lock(mutex_);
    now = current_;
    count = previous_.size();
    if (!previous_.empty()) before = previous_.back();
  }
  out->set_generation(now->generation);
  out->set_yaml(calib::toSystemCalibrationYaml(now->calibration));
  out->set_source(now->source);
  out->set_applied_ns(now->applied_ns);
  out->set_previous(static_cast<std::uint32_t>(count));
  out->set_previous_source(before ? before->source : std::string());
  std::lock_guard lock(mutex_);
  out->set_saved_to(saved_to_);
  out->set_save_error(save_error_);
}

link::proto::ControlReply CalibrationInUse::handleControl(const link::proto::ControlRequest& request) {
  link::proto::ControlReply reply;
  reply.set_id(request.id());
  std::string error;
  switch (request.request_case()) {
    case link::proto::ControlRequest::kApplyCalibration: {
      const auto parsed = calib::parseCalibration(request.apply_calibration().text(), "apply_calibration");
      if (!parsed) {
        reply.set_error("calibration not applied: " + parsed.error().describe());
        break;
      }
      if (apply(*parsed, request.apply_calibration().source(), &error))
        reply.set_ok(true);
      else
        reply.set_error(error);
      break;
    }
    case link::proto::ControlRequest::kRevertCalibration:
      if (revert(&error))
        reply.set_ok(true);
      else
        reply.set_error(error);
      break;
    case link::proto::ControlRequest::kGetCalibration: reply.set_ok(true); break;
    default: reply.set_error("not a calibration request"); return reply;
  }
  fill(reply.mutable_calibration());
  return reply;
}

StereoCameraPoses CalibrationInUse::posesAt(const JointStateBuffer& joints, const arm::JointVector& q_fallback,
                                            std::int64_t left_capture_ns, std::int64_t right_capture_ns) const {
  const std::shared_ptr<const AppliedCalibration> in_use = current();
  const Eigen::Isometry3d T_flange_cam_l = in_use->geometry.T_flange_cam_l;
  const Eigen::Isometry3d T_flange_cam_r = T_flange_cam_l * in_use->geometry.T_cam_l_cam_r;
  StereoCameraPoses poses;
  poses.calibration_generation = in_use->generation;
  auto left = joints.T_robot_flange(left_capture_ns);
  auto right = joints.T_robot_flange(right_capture_ns);
  poses.measured_l = left.has_value();
  poses.measured_r = right.has_value();
  if (!left || !right) {  // before the arm's first state (or a gap): the initial configuration
    const Eigen::Isometry3d T_robot_flange0 = kinematics_.forward(q_fallback);
    if (!left) left = T_robot_flange0;
    if (!right) right = T_robot_flange0;
  }
  poses.T_robot_cam_l = *left * T_flange_cam_l;
  poses.T_robot_cam_r = *right * T_flange_cam_r;
  return poses;
}

}  // namespace telesphere::robot::head
