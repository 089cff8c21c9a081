// SPDX-License-Identifier: MIT
/// @brief GroundTruthLog (see ground_truth_log.h).
#include "robot/stereo/ground_truth_log.h"

#include <cerrno>
#include <cstring>

#include "robot/link/link_pose.h"
#include "robot/link/pose_csv.h"

namespace telesphere::robot::stereo {
namespace {

void writeMissingPose(std::ostream& out) { out << ",,,,,,,"; }

}  // namespace

std::unique_ptr<GroundTruthLog> GroundTruthLog::open(const std::string& path, const head::JointStateBuffer& truth,
                                                     std::string* error) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) {
    *error = "cannot write the ground truth to " + path + ": " + std::strerror(errno);
    return nullptr;
  }
  out.precision(17);
  out << "sequence,capture_ns_left,capture_ns_right";
  out << link::poseCsvHeader("true_left") << link::poseCsvHeader("true_right") << ",mapping_set"
      << link::poseCsvHeader("robot_vr") << '\n';
  return std::unique_ptr<GroundTruthLog>(new GroundTruthLog(std::move(out), truth));
}

GroundTruthLog::GroundTruthLog(std::ofstream out, const head::JointStateBuffer& truth)
    : out_(std::move(out)), truth_(truth) {}

void GroundTruthLog::frameSent(const StereoFrame& pair, std::uint64_t sequence,
                               const link::proto::NominalMapping& mapping) {
  std::lock_guard lock(mutex_);
  out_ << sequence << ',' << pair.left.capture_ns << ',' << pair.right.capture_ns;
  for (const auto& [side, frame] : {std::pair{cameras::CameraSide::kLeft, &pair.left}, std::pair{cameras::CameraSide::kRight, &pair.right}}) {
    if (const auto T = truth_.T_robot_cam(side, frame->capture_ns)) {
      link::writePoseCsv(out_, *T);
    } else {
      writeMissingPose(out_);
    }
  }
  out_ << ',' << (mapping.mapping_set() ? 1 : 0);
  link::writePoseCsv(out_, link::fromLinkPose(mapping.t_robot_vr()));
  out_ << '\n';
  out_.flush();  // the bench reads it while the robot runs, and a killed robot keeps its rows
  ++rows_;
}

std::uint64_t GroundTruthLog::rows() const {
  std::lock_guard lock(mutex_);
  return rows_;
}

}  // namespace telesphere::robot::stereo
