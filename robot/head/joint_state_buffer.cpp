// SPDX-License-Identifier: MIT
/// @brief JointStateBuffer (see joint_state_buffer.h).
#include "robot/head/joint_state_buffer.h"

#include <mutex>

#include "calib/debug_assert.h"

namespace telesphere::robot::head {

JointStateBuffer::JointStateBuffer(const HeadGeometry& geometry,
                                   const JointStateBufferConfig& config)
    : T_flange_cam_l_(geometry.T_flange_cam_l),
      T_flange_cam_r_(geometry.T_flange_cam_l * geometry.T_cam_l_cam_r),
      config_(config),
      ring_(config.capacity) {
  TS_ASSERT(config.capacity >= 2 && config.max_extrapolation_ns >= 0 && config.max_gap_ns > 0,
            config.capacity, config.max_extrapolation_ns, config.max_gap_ns);
}

const arm::JointState& JointStateBuffer::at(std::size_t i) const {
  return ring_[(begin_ + i) % ring_.size()];
}

bool JointStateBuffer::push(const arm::JointState& state) {
  if (!state.q.allFinite()) return false;
  std::unique_lock lock(mutex_);
  if (size_ > 0 && state.t_ns <= at(size_ - 1).t_ns) return false;
  if (size_ == ring_.size()) {
    ring_[begin_] = state;
    begin_ = (begin_ + 1) % ring_.size();
  } else {
    ring_[(begin_ + size_) % ring_.size()] = state;
    ++size_;
  }
  lock.unlock();
  pushed_.notify_all();
  return true;
}

bool JointStateBuffer::waitForSampleAtOrAfter(std::int64_t t_ns, std::chrono::steady_clock::time_point deadline) const {
  std::shared_lock lock(mutex_);
  ++waiting_readers_;
  const bool reached = pushed_.wait_until(lock, deadline, [&] { return size_ > 0 && at(size_ - 1).t_ns >= t_ns; });
  --waiting_readers_;
  return reached;
}

std::optional<arm::JointVector> JointStateBuffer::jointsAt(std::int64_t t_ns) const {
  std::shared_lock lock(mutex_);
  if (size_ == 0) return std::nullopt;
  const arm::JointState& oldest = at(0);
  const arm::JointState& newest = at(size_ - 1);
  if (t_ns < oldest.t_ns) return std::nullopt;
  if (t_ns >= newest.t_ns) {
    if (t_ns - newest.t_ns > config_.max_extrapolation_ns) return std::nullopt;
    if (size_ == 1 || t_ns == newest.t_ns) return newest.q;
    const arm::JointState& before = at(size_ - 2);
    if (newest.t_ns - before.t_ns > config_.max_gap_ns) return newest.q;
    const double s = static_cast<double>(t_ns - before.t_ns) /
                     static_cast<double>(newest.t_ns - before.t_ns);
    return arm::JointVector(before.q + s * (newest.q - before.q));
  }
  // Binary search for the last sample at or before t (oldest.t ≤ t < newest.t here).
  std::size_t lo = 0, hi = size_ - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (at(mid).t_ns <= t_ns ? lo : hi) = mid;
  }
  const arm::JointState& a = at(lo);
  const arm::JointState& b = at(hi);
  if (t_ns == a.t_ns) return a.q;
  if (b.t_ns - a.t_ns > config_.max_gap_ns) return std::nullopt;
  const double s = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return arm::JointVector(a.q + s * (b.q - a.q));
}

std::optional<Eigen::Isometry3d> JointStateBuffer::T_robot_flange(std::int64_t t_ns) const {
  const std::optional<arm::JointVector> q = jointsAt(t_ns);
  if (!q) return std::nullopt;
  return kinematics_.forward(*q);
}

std::optional<Eigen::Isometry3d> JointStateBuffer::T_robot_cam(cameras::CameraSide side,
                                                              std::int64_t t_ns) const {
  const std::optional<Eigen::Isometry3d> T = T_robot_flange(t_ns);
  if (!T) return std::nullopt;
  std::shared_lock lock(mutex_);
  return *T * (side == cameras::CameraSide::kLeft ? T_flange_cam_l_ : T_flange_cam_r_);
}

void JointStateBuffer::setGeometry(const HeadGeometry& geometry) {
  std::unique_lock lock(mutex_);
  T_flange_cam_l_ = geometry.T_flange_cam_l;
  T_flange_cam_r_ = geometry.T_flange_cam_l * geometry.T_cam_l_cam_r;
}

std::size_t JointStateBuffer::size() const {
  std::shared_lock lock(mutex_);
  return size_;
}

std::optional<std::pair<std::int64_t, std::int64_t>> JointStateBuffer::window() const {
  std::shared_lock lock(mutex_);
  if (size_ == 0) return std::nullopt;
  return std::make_pair(at(0).t_ns, at(size_ - 1).t_ns);
}

std::optional<std::pair<std::int64_t, std::int64_t>> JointStateBuffer::bracket(std::int64_t t_ns) const {
  std::shared_lock lock(mutex_);
  if (size_ == 0 || t_ns < at(0).t_ns || t_ns > at(size_ - 1).t_ns) return std::nullopt;
  std::int64_t before = at(0).t_ns;
  for (std::size_t i = 0; i < size_; ++i) {
    const std::int64_t t = at(i).t_ns;
    if (t >= t_ns) return std::make_pair(t == t_ns ? t : before, t);
    before = t;
  }
  return std::nullopt;
}

}  // namespace telesphere::robot::head
