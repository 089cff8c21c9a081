// SPDX-License-Identifier: MIT
/// @brief SimulatedArm (see head_arm_sim.h).
#include "robot/arm/head_arm_sim.h"

#include <algorithm>
#include <cmath>

#include "calib/debug_assert.h"

namespace telesphere::robot::arm {

SimulatedArm::SimulatedArm(const clock::Clock& clock, const SimulatedArmConfig& config)
    : clock_(clock), config_(config), rng_(config.seed) {
  TS_ASSERT(config.command_latency_ns >= 0 && config.max_velocity > 0 &&
                config.max_acceleration > 0 && config.encoder_noise_std >= 0 &&
                config.state_period_ns > 0 && config.physics_step_ns > 0 &&
                config.state_period_ns % config.physics_step_ns == 0,
            config.command_latency_ns, config.max_velocity, config.max_acceleration,
            config.encoder_noise_std, config.state_period_ns, config.physics_step_ns);
  q_ = kinematics_.clampToLimits(config.q_initial);
  v_.setZero();
  set_point_ = q_;
  // Physics runs on absolute multiples of the step, starting at the last one before now.
  const std::int64_t now = clock_.nowNs();
  t_ns_ = now - ((now % config_.physics_step_ns) + config_.physics_step_ns) % config_.physics_step_ns;
}

void SimulatedArm::update() {
  const std::int64_t now = clock_.nowNs();
  while (t_ns_ + config_.physics_step_ns <= now) {
    step(config_.physics_step_ns);
    if (t_ns_ % config_.state_period_ns == 0) publishState();
  }
}

bool SimulatedArm::sendTarget(const JointVector& q_target) {
  if (stopped_ || !connected_ || !kinematics_.withinLimits(q_target)) {
    ++refused_targets_;
    return false;
  }
  in_flight_.emplace_back(clock_.nowNs() + config_.command_latency_ns, q_target);
  return true;
}

std::optional<JointState> SimulatedArm::pollState() {
  if (!connected_ || states_.empty()) return std::nullopt;
  JointState s = states_.front();
  states_.pop_front();
  return s;
}

ArmStatus SimulatedArm::status() const {
  if (!connected_) return ArmStatus::kDisconnected;
  return stopped_ ? ArmStatus::kStopped : ArmStatus::kOk;
}

bool SimulatedArm::clearStop() {
  if (!connected_) return false;
  stopped_ = false;
  stop_text_.clear();
  return true;
}

void SimulatedArm::stop() {
  const bool own_fault = stopped_ && stop_text_ != kStoppedOnRequest;
  triggerStop();
  if (!own_fault) stop_text_ = kStoppedOnRequest;
}

std::string SimulatedArm::faultText() const {
  if (!connected_) return "the connection to the arm dropped";
  return stopped_ ? stop_text_ : std::string();
}

void SimulatedArm::triggerStop() {
  stopped_ = true;
  stop_text_ = "emergency stop";
  in_flight_.clear();
  // Brake as hard as allowed: the set-point becomes the stopping point of each joint.
  for (int i = 0; i < 6; ++i)
    set_point_[i] = q_[i] + v_[i] * std::abs(v_[i]) / (2.0 * config_.max_acceleration);
  set_point_ = kinematics_.clampToLimits(set_point_);
}

void SimulatedArm::dropConnection() {
  connected_ = false;
  in_flight_.clear();
}

void SimulatedArm::reconnect() { connected_ = true; }

void SimulatedArm::step(std::int64_t dt_ns) {
  const std::int64_t t_next = t_ns_ + dt_ns;
  while (!in_flight_.empty() && in_flight_.front().first <= t_ns_) {
    if (!stopped_) set_point_ = in_flight_.front().second;
    in_flight_.pop_front();
  }
  const double dt = static_cast<double>(dt_ns) * 1e-9;
  const double a_max = config_.max_acceleration, v_max = config_.max_velocity;
  for (int i = 0; i < 6; ++i) {
    const double e = set_point_[i] - q_[i];
    if (v_[i] == 0.0 && std::abs(e) < config_.breakaway_rad) continue;  // static friction holds it
    if (std::abs(e) <= 0.5 * a_max * dt * dt && std::abs(v_[i]) <= a_max * dt) {
      q_[i] = set_point_[i];
      v_[i] = 0;
      continue;
    }
    // The fastest velocity from which the joint can still brake to a stop on the set-point
    // (one step of braking accounted for), then accelerate towards it within the limit.
    const double braking = std::sqrt(std::max(0.0, 2.0 * a_max * std::abs(e) - a_max * dt * a_max * dt)) ;
    const double v_wanted = std::copysign(std::min(v_max, braking), e);
    v_[i] += std::clamp(v_wanted - v_[i], -a_max * dt, a_max * dt);
    q_[i] += v_[i] * dt;
  }
  // Hard stops at the joint limits.
  for (int i = 0; i < 6; ++i) {
    const double clamped =
        std::clamp(q_[i], kinematics_.lowerLimits()[i], kinematics_.upperLimits()[i]);
    if (clamped != q_[i]) {
      q_[i] = clamped;
      v_[i] = 0;
    }
  }
  t_ns_ = t_next;
  if (config_.on_true_state) {
    JointState truth;
    truth.t_ns = t_ns_;
    truth.q = q_;
    truth.status = stopped_ ? ArmStatus::kStopped : connected_ ? ArmStatus::kOk : ArmStatus::kDisconnected;
    config_.on_true_state(truth);
  }
}

void SimulatedArm::publishState() {
  if (!connected_) return;
  JointState s;
  s.t_ns = t_ns_;
  for (int i = 0; i < 6; ++i) s.q[i] = q_[i] + config_.encoder_noise_std * noise_(rng_);
  s.status = stopped_ ? ArmStatus::kStopped : ArmStatus::kOk;
  states_.push_back(s);
  while (states_.size() > config_.max_queued_states) states_.pop_front();
}

}  // namespace telesphere::robot::arm
