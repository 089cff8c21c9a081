// SPDX-License-Identifier: MIT
/// @brief SimulatedArm: an xArm 6 head arm in software that behaves like the real one (per-joint
///        velocity and acceleration limits, command-to-motion latency, encoder noise, joint limits,
///        stops and dropped connections), run on a Clock that tests drive (no sleeps, no threads).
///
/// Model: a target sent at time t becomes the servo set-point at t + command_latency_ns (the
/// latency of the real arm's command path and servo loop lumped into one dead time). Each joint
/// then moves towards its set-point on a velocity- and acceleration-limited profile (it brakes
/// so as to stop on the set-point), integrated in physics_step_ns steps on absolute time
/// multiples of the step. A joint state, with Gaussian encoder noise, is published at every
/// multiple of state_period_ns. Not thread-safe: one control loop owns it.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <utility>

#include "robot/clock/clock.h"
#include "robot/arm/head_arm.h"
#include "robot/arm/xarm6_kinematics.h"

namespace telesphere::robot::arm {

struct SimulatedArmConfig {
  /// Dead time from sendTarget() to the set-point reaching the servos: not published (the
  /// controller takes servo targets at up to 250 Hz, "no buffer"); fitted so that the replayed
  /// 0.5 m/s head motion of the paper's Fig. 6 starts ≈ latency + 12 ms after the operator (start
  /// latency t1 ≈ 130 ms, the paper's figure); it stops ≈ latency + 23 ms after (t2);
  /// `telesphere-bench head` and robot/README.md give the map.
  std::int64_t command_latency_ns = 118'000'000;
  /// rad/s per joint: 180°/s, the xArm 6's published maximum joint speed (UFACTORY robot
  /// specifications; servo mode moves "with the fastest speed (180°/s)", user manual).
  double max_velocity = 3.14159265358979323846;
  /// rad/s² per joint: 1145°/s², the top of the published joint acceleration range of the
  /// xArm 5/6/7 (and the SDK's max_joint_acc, 20 rad/s²). The published jerk limit (28647°/s³)
  /// is not modelled: at 500 rad/s³ it shapes only the first 40 ms of a full-acceleration ramp.
  double max_acceleration = 20.0;
  double encoder_noise_std = 2e-5;               ///< rad, Gaussian, per joint and state
  /// Static friction: a joint at rest starts only once its set-point is this far away (rad);
  /// once moving it tracks time-optimally. 0 (the default): none. Fitted to the paper's Fig. 6
  /// it would need about 20 mrad with a 70 ms dead time (telesphere-bench head, robot/README.md),
  /// a dead band a real xArm does not have, so it is off.
  double breakaway_rad = 0.0;
  std::int64_t state_period_ns = HeadArm::kStatePeriodNs;
  std::int64_t physics_step_ns = 1'000'000;
  std::uint64_t seed = 1;                        ///< of the encoder noise
  JointVector q_initial = JointVector::Zero();   ///< rad, clamped into the limits
  std::size_t max_queued_states = 1000;          ///< older untaken states are dropped
  /// Ground truth: called with the noise-free joints after every physics step, on the thread
  /// that calls update() (the synthetic cameras render at these poses; tests and benchmarks
  /// compare with them). A real arm has nothing like it.
  std::function<void(const JointState&)> on_true_state;
};

class SimulatedArm final : public HeadArm {
 public:
  SimulatedArm(const clock::Clock& clock, const SimulatedArmConfig& config = {});

  void update() override;
  bool sendTarget(const JointVector& q_target) override;
  std::optional<JointState> pollState() override;
  ArmStatus status() const override;
  bool clearStop() override;
  /// Brakes as triggerStop() does; faultText() says kStoppedOnRequest (unless the arm had a
  /// fault of its own already).
  void stop() override;
  std::string faultText() const override;

  /// Fault injection: an emergency stop. The arm brakes at its acceleration limit and holds;
  /// targets in flight are lost; sendTarget() fails until clearStop(). faultText(): "emergency stop".
  void triggerStop();
  /// Fault injection: the connection drops. No states arrive, targets in flight are lost and
  /// sendTarget() fails; the arm finishes the set-point it had. reconnect() restores the link.
  void dropConnection();
  void reconnect();

  /// Ground truth for tests and benchmarks (not available from a real arm).
  const JointVector& trueJoints() const { return q_; }
  const JointVector& trueVelocities() const { return v_; }
  const JointVector& setPoint() const { return set_point_; }
  std::int64_t simulatedUntilNs() const { return t_ns_; }
  /// How many targets sendTarget() refused (fault, disconnected, non-finite, beyond limits).
  std::int64_t refusedTargets() const { return refused_targets_; }
  const Xarm6Kinematics& kinematics() const { return kinematics_; }
  const SimulatedArmConfig& config() const { return config_; }

 private:
  void step(std::int64_t dt_ns);
  void publishState();

  const clock::Clock& clock_;
  SimulatedArmConfig config_;
  Xarm6Kinematics kinematics_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
  std::int64_t t_ns_ = 0;  ///< physics time: everything up to here is simulated
  JointVector q_, v_, set_point_;
  std::deque<std::pair<std::int64_t, JointVector>> in_flight_;  ///< (t_effective_ns, target)
  std::deque<JointState> states_;
  bool stopped_ = false, connected_ = true;
  std::string stop_text_;  ///< why stopped_: kStoppedOnRequest or the injected fault
  std::int64_t refused_targets_ = 0;
};

}  // namespace telesphere::robot::arm
