// SPDX-License-Identifier: MIT
/// @brief Everything telesphere-robot runs, wired together (only app/ wires concrete types;
///        DESIGN.md §1, §4, §5):
///          cameras → stereo pairing → parallel JPEG encode → link (frames, with T_robot_cam at
///          capture time from the joint-state buffer)
///          link (head targets) → head controller → arm → joint-state buffer → link (state)
///        plus the console's services (preview, calibration stills, control, health). The arm is
///        the simulated xArm 6 or a real one (XArmHeadArm, --arm xarm); the cameras are synthetic (rendering the default scene through the
///        true calibration at the arm's true pose, TrueCameraPoses) or GenICam cameras (Aravis).
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "app/robot_options.h"

namespace telesphere::app {

class RobotAssembly {
 public:
  /// Loads the calibration(s), starts the arm (a real one moves to the nominal joints), opens the
  /// link and starts the cameras. Null on failure, with *exit_code 1 (bad arguments or files) or
  /// 2 (the arm, a camera or the link could not start) and the reason in *error.
  static std::unique_ptr<RobotAssembly> build(const RobotOptions& options, int* exit_code, std::string* error);
  ~RobotAssembly();
  RobotAssembly(const RobotAssembly&) = delete;
  RobotAssembly& operator=(const RobotAssembly&) = delete;

  /// Runs until `stop` is set (or options.duration_s has passed, which sets it): the head loop,
  /// the manipulator's reports, preview, pairing and video on their threads; health on the link
  /// every 500 ms and a statistics line on stderr every options.stats_period_s. Then stops
  /// everything in order. Returns the frames sent.
  std::uint64_t run(std::atomic<bool>& stop);

  /// "simulated arm, synthetic cameras 640x360 at 45 Hz, link on port 5760"
  std::string describe() const;

  struct Parts;  ///< what is wired (robot_assembly.cpp)

 private:
  explicit RobotAssembly(std::unique_ptr<Parts> parts);
  std::unique_ptr<Parts> parts_;
};

}  // namespace telesphere::app
