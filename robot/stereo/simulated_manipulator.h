// SPDX-License-Identifier: MIT
/// @brief The manipulator arm that carries the wrist marker for hand-eye calibration (paper
///        §III-B, fig. "calibration frames"), simulated so that the whole procedure runs on one
///        laptop: an xArm 6 standing at T_robot_mount, moved along a scripted teach-mode path
///        (each joint a sinusoid about a home configuration, periods that never line up), its
///        joints reported at 100 Hz with encoder noise like a real arm's, and the marker placed
///        at T_robot_marker(t) = T_robot_mount · FK(q(t)) · T_wrist_marker for the synthetic
///        cameras (exactly, between reports too).
///
/// Driven like SimulatedArm: update(now) publishes every report due by `now` into the
/// JointStateBuffer given (no thread of its own, no sleeps). The manipulator's forward
/// kinematics are the xArm 6 model of robot/arm/xarm6_kinematics.h; that buffer's "flange" pose is
/// then T_mount_wrist.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include "robot/arm/joint_state.h"
#include "robot/head/joint_state_buffer.h"
#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot::stereo {

/// Where the manipulator stands and where its marker sits (the two transforms the hand-eye
/// calibration recovers besides T_flange_cam_l).
struct ManipulatorMounting {
  Eigen::Isometry3d T_robot_mount = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_wrist_marker = Eigen::Isometry3d::Identity();

  /// The default scene's manipulator: across the table, 1.45 m ahead of the robot base and
  /// 0.35 m to its left, turned to face the head; the marker 35 mm in front of the flange,
  /// turned 90° about the flange axis.
  static ManipulatorMounting example();
};

struct SimulatedManipulatorConfig {
  ManipulatorMounting mounting = ManipulatorMounting::example();
  /// The marker's pose at the home configuration, robot frame (default: the centre of the
  /// default scene's marker circle, DefaultSceneLayout::T_robot_marker_centre(), turned to face
  /// the head).
  std::optional<Eigen::Isometry3d> T_robot_marker_home;
  /// Teach-mode path: q(t) = q_home + amplitude ⊙ sin(2π t / period + phase), rad and s. The
  /// wrist joints swing most (the marker turns about three axes, ≤ 30° from facing the head).
  arm::JointVector amplitude_rad = (arm::JointVector() << 0.06, 0.05, 0.05, 0.30, 0.25, 0.35).finished();
  arm::JointVector period_s = (arm::JointVector() << 13.0, 17.0, 19.0, 11.0, 7.0, 9.0).finished();
  arm::JointVector phase_rad = (arm::JointVector() << 0.0, 1.0, 2.0, 0.5, 1.5, 2.5).finished();
  std::int64_t report_period_ns = 10'000'000;  ///< 100 Hz, like the head arm
  double encoder_noise_std = 2e-5;             ///< rad, Gaussian, per joint and report
  std::uint64_t seed = 7;
};

class SimulatedManipulator {
 public:
  /// The home configuration is found by inverse kinematics; nothing (with the reason in *error)
  /// when the manipulator cannot reach the marker's home pose from its mount.
  static std::optional<SimulatedManipulator> create(const SimulatedManipulatorConfig& config, std::string* error);

  /// Publishes every report due at or before now_ns (multiples of the report period) into
  /// `reports`; the first call publishes only the report at now_ns's period.
  void update(std::int64_t now_ns, head::JointStateBuffer& reports);

  /// The true path: joints, T_mount_wrist = FK(q), and the marker in the robot frame.
  arm::JointVector q(std::int64_t t_ns) const;
  Eigen::Isometry3d T_mount_wrist(std::int64_t t_ns) const;
  Eigen::Isometry3d T_robot_marker(std::int64_t t_ns) const;

  const arm::JointVector& qHome() const { return q_home_; }
  const SimulatedManipulatorConfig& config() const { return config_; }

 private:
  SimulatedManipulator(const SimulatedManipulatorConfig& config, const arm::JointVector& q_home)
      : config_(config), q_home_(q_home), rng_(config.seed) {}

  SimulatedManipulatorConfig config_;
  arm::Xarm6Kinematics kinematics_;
  arm::JointVector q_home_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
  std::int64_t next_report_ns_ = 0;
  bool started_ = false;
};

}  // namespace telesphere::robot::stereo
