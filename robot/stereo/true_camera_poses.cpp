// SPDX-License-Identifier: MIT
#include "robot/stereo/true_camera_poses.h"

#include <iostream>

namespace telesphere::robot::stereo {

Eigen::Isometry3d TrueCameraPoses::at(cameras::CameraSide side, std::int64_t t_ns) const {
  // Wait for the simulation to pass t (woken by each state it pushes), unless t comes before the
  // arm's first state.
  if (truth_.window() || clock_.nowNs() >= t_ns)
    truth_.waitForSampleAtOrAfter(t_ns, std::chrono::steady_clock::now() + max_wait_);
  if (const auto T = truth_.T_robot_cam(side, t_ns)) return *T;
  if (truth_.window() && fallbacks_.fetch_add(1) % 100 == 0)
    std::cerr << "telesphere-robot: synthetic camera: no true arm pose at the capture time after "
              << max_wait_.count() << " ms (the head loop is stalled); the frame shows the initial pose ("
              << fallbacks_.load() << " so far)\n";
  return T_robot_cam0_[side == cameras::CameraSide::kLeft ? 0 : 1];
}

}  // namespace telesphere::robot::stereo
