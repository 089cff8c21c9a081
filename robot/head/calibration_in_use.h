// SPDX-License-Identifier: MIT
/// @brief The calibration the robot uses, changed live (DESIGN.md §6; link ApplyCalibration,
///        revert_calibration, get_calibration): the console's wizards apply a result without a
///        restart, and the supervisor can go back.
///
/// Every change makes a new generation (1: the start-up calibration), held as an immutable
/// snapshot: the video path stamps each frame's camera poses from one snapshot and names its
/// generation in the frame (so the XR app knows which camera models go with it); the head loop
/// takes a new one at its next tick (controller and joint-state buffer). An applied calibration
/// is merged onto the one in use: fields it lacks (T_flange_cam_l after an intrinsics
/// calibration, the manipulator's transforms) keep their values. Refused with the reason when
/// the result is inconsistent, lacks two cameras, T_cam_l_cam_r or T_flange_cam_l, or a camera
/// cannot be scaled to the image size of the calibration in use (another aspect ratio: not
/// these cameras). The replaced calibrations are kept (kMaxPrevious) for revert.
///
/// Thread safety: every member may be called from any thread.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "calib/system_calibration.h"
#include "robot/clock/clock.h"
#include "robot/head/head_geometry.h"
#include "robot/head/joint_state_buffer.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::robot::head {

/// One generation of the calibration in use.
struct AppliedCalibration {
  std::uint64_t generation = 1;
  calib::SystemCalibration calibration;  ///< two cameras, T_cam_l_cam_r and T_flange_cam_l present
  HeadGeometry geometry;                 ///< its camera mount
  std::string source;                    ///< what it is ("--calib FILE", "hand-eye wizard …")
  std::int64_t applied_ns = 0;           ///< robot clock
};

/// Where both cameras of a stereo pair were at their capture times, and which calibration said so.
struct StereoCameraPoses {
  Eigen::Isometry3d T_robot_cam_l = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_robot_cam_r = Eigen::Isometry3d::Identity();
  /// From joint states at the capture time; false: the calibrated pose at the arm's initial
  /// configuration (link POSE_SOURCE_FIXED_CALIBRATION).
  bool measured_l = false, measured_r = false;
  std::uint64_t calibration_generation = 0;  ///< 0: not from a CalibrationInUse
};

class CalibrationInUse {
 public:
  static constexpr std::size_t kMaxPrevious = 16;

  /// Starts with `startup` (generation 1); throws std::invalid_argument when it is unusable().
  CalibrationInUse(const calib::SystemCalibration& startup, std::string source, const clock::Clock& clock);

  /// Why `calibration` cannot be the robot's, or nothing: inconsistent, not two cameras, no
  /// T_cam_l_cam_r or T_flange_cam_l.
  static std::optional<std::string> unusable(const calib::SystemCalibration& calibration);

  std::shared_ptr<const AppliedCalibration> current() const;
  /// How many calibrations revert can go back through.
  std::size_t previousCount() const;

  /// Merges `applied` onto the calibration in use and makes it current. False with the reason
  /// (nothing changes) when the result is unusable or does not fit these cameras.
  bool apply(const calib::SystemCalibration& applied, std::string source, std::string* error);
  /// Back to the calibration before the last apply (as a new generation). False when there is none.
  bool revert(std::string* error);

  /// Where every calibration applied or reverted to is saved (our YAML, written to a temporary
  /// file and renamed over `path`), so that `telesphere-robot --calib path` after a restart keeps
  /// it (`--calib-save`); empty: nothing is saved, and the link's view says so.
  void setSavePath(std::string path);

  /// The link's view of the calibration in use (the YAML text in our format; where it was saved).
  void fill(link::proto::CalibrationInUse* out) const;
  /// Answers apply_calibration, revert_calibration and get_calibration (others: refused).
  link::proto::ControlReply handleControl(const link::proto::ControlRequest& request);

  /// Both cameras' poses at their capture times through the calibration in use: FK of the
  /// joints interpolated by `joints`, else (no joint state at that time) FK(q_fallback).
  StereoCameraPoses posesAt(const JointStateBuffer& joints, const arm::JointVector& q_fallback,
                            std::int64_t left_capture_ns, std::int64_t right_capture_ns) const;

 private:
  void install(AppliedCalibration next);  ///< caller holds mutex_

  const clock::Clock& clock_;
  arm::Xarm6Kinematics kinematics_;
  mutable std::mutex mutex_;
  std::shared_ptr<const AppliedCalibration> current_;
  std::vector<std::shared_ptr<const AppliedCalibration>> previous_;  ///< oldest first
  std::uint64_t next_generation_ = 2;
  std::string save_path_;
  std::string saved_to_, save_error_;  ///< of the current generation
};

}  // namespace telesphere::robot::head
