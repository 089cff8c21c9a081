// SPDX-License-Identifier: MIT
/// @brief SimulatedManipulator (see simulated_manipulator.h).
#include "robot/stereo/simulated_manipulator.h"

#include <cmath>

#include "robot/cameras/synthetic_scene.h"

namespace telesphere::robot::stereo {

ManipulatorMounting ManipulatorMounting::example() {
  ManipulatorMounting m;
  m.T_robot_mount.translation() = Eigen::Vector3d(1.45, 0.35, 0.10);
  m.T_robot_mount.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  m.T_wrist_marker.translation() = Eigen::Vector3d(0.0, 0.0, 0.035);
  m.T_wrist_marker.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return m;
}

std::optional<SimulatedManipulator> SimulatedManipulator::create(const SimulatedManipulatorConfig& config,
                                                                 std::string* error) {
  const ManipulatorMounting& m = config.mounting;
  if (!m.T_robot_mount.matrix().allFinite() || !m.T_wrist_marker.matrix().allFinite() ||
      !config.amplitude_rad.allFinite() || !(config.period_s.minCoeff() > 0) || config.report_period_ns <= 0) {
    *error = "simulated manipulator: mounting, amplitudes and periods must be finite and the periods positive";
    return std::nullopt;
  }
  // By default the marker sits at the centre of the default scene's marker circle, turned to
  // face the head (marker z towards it, marker x level).
  Eigen::Isometry3d T_robot_marker = cameras::DefaultSceneLayout::T_robot_marker_centre();
  if (config.T_robot_marker_home) {
    T_robot_marker = *config.T_robot_marker_home;
  } else {
    const Eigen::Vector3d z = (cameras::DefaultSceneLayout{}.head_position - T_robot_marker.translation()).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(z).normalized();
    T_robot_marker.linear().col(0) = x;
    T_robot_marker.linear().col(1) = z.cross(x);
    T_robot_marker.linear().col(2) = z;
  }
  const Eigen::Isometry3d T_mount_flange = m.T_robot_mount.inverse() * T_robot_marker * m.T_wrist_marker.inverse();
  const arm::Xarm6Kinematics kinematics;
  arm::IkOptions options;
  options.max_iterations = 300;
  // A few seeds: the elbow up and down, the base turned towards the target.
  const double yaw = std::atan2(T_mount_flange.translation().y(), T_mount_flange.translation().x());
  for (const arm::JointVector& seed : {arm::JointVector((arm::JointVector() << yaw, -0.3, -0.8, 0.0, 1.1, 0.0).finished()),
                                  arm::JointVector((arm::JointVector() << yaw, 0.3, -1.2, 0.0, 0.9, 0.0).finished()),
                                  arm::JointVector(arm::JointVector::Zero())}) {
    const arm::IkResult ik = kinematics.inverse(T_mount_flange, seed, options);
    if (ik.status != arm::IkResult::Status::kConverged) continue;
    // The path must stay inside the joint limits.
    if (!kinematics.withinLimits(ik.q - config.amplitude_rad.cwiseAbs()) ||
        !kinematics.withinLimits(ik.q + config.amplitude_rad.cwiseAbs()))
      continue;
    return SimulatedManipulator(config, ik.q);
  }
  const Eigen::Vector3d p = T_mount_flange.translation();
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "simulated manipulator: from its mount it cannot reach the marker's place in the scene (flange "
                "at %.3f, %.3f, %.3f m in the mount frame) with room for its teach-mode path",
                p.x(), p.y(), p.z());
  *error = buf;
  return std::nullopt;
}

arm::JointVector SimulatedManipulator::q(std::int64_t t_ns) const {
  const double t = static_cast<double>(t_ns) * 1e-9;
  arm::JointVector q = q_home_;
  for (int i = 0; i < 6; ++i) {
    // fmod keeps the phase exact for large steady-clock times.
    const double cycle = std::fmod(t, config_.period_s[i]) / config_.period_s[i];
    q[i] += config_.amplitude_rad[i] * std::sin(2.0 * M_PI * cycle + config_.phase_rad[i]);
  }
  return q;
}

Eigen::Isometry3d SimulatedManipulator::T_mount_wrist(std::int64_t t_ns) const { return kinematics_.forward(q(t_ns)); }

Eigen::Isometry3d SimulatedManipulator::T_robot_marker(std::int64_t t_ns) const {
  return config_.mounting.T_robot_mount * T_mount_wrist(t_ns) * config_.mounting.T_wrist_marker;
}

void SimulatedManipulator::update(std::int64_t now_ns, head::JointStateBuffer& reports) {
  const std::int64_t period = config_.report_period_ns;
  if (!started_) {
    next_report_ns_ = now_ns - now_ns % period;
    started_ = true;
  }
  for (; next_report_ns_ <= now_ns; next_report_ns_ += period) {
    arm::JointState s;
    s.t_ns = next_report_ns_;
    s.q = q(next_report_ns_);
    for (int i = 0; i < 6; ++i) s.q[i] += config_.encoder_noise_std * noise_(rng_);
    reports.push(s);
  }
}

}  // namespace telesphere::robot::stereo
