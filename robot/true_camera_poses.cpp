// SPDX-License-Identifier: MIT
#include "robot/true_camera_poses.h"

#include <iostream>
#include <thread>

namespace telesphere::robot {

Eigen::Isometry3d TrueCameraPoses::at(CameraSide side, std::int64_t t_ns) const {
  const auto give_up = std::chrono::steady_clock::now() + max_wait_;
  for (;;) {
    const auto window = truth_.window();
    if (window && window->second >= t_ns) break;          // simulated past t: the truth is there
    if (!window && clock_.nowNs() < t_ns) break;          // before the arm's first state
    if (std::chrono::steady_clock::now() >= give_up) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (const auto T = truth_.T_robot_cam(side, t_ns)) return *T;
  if (truth_.window() && fallbacks_.fetch_add(1) % 100 == 0)
    std::cerr << "telesphere-robot: synthetic camera: no true arm pose at the capture time after "
              << max_wait_.count() << " ms (the head loop is stalled); the frame shows the initial pose ("
              << fallbacks_.load() << " so far)\n";
  return T_robot_cam0_[side == CameraSide::kLeft ? 0 : 1];
}

}  // namespace telesphere::robot
