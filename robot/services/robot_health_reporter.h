// SPDX-License-Identifier: MIT
/// @brief The robot's health summary for the console (link RobotHealth, a few times a second):
///        cameras (fps over the last period, frames, drops by reason, exposure, reconnects, last
///        error), stereo pairing and encoding, the link's drops by reason, the head loop's and the
///        arm's state (with the real xArm's link figures, refusals and payload), the settings in
///        force, and this process's identity. Built from the
///        counters each part already keeps; nothing is counted twice.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot/cameras/camera_source.h"
#include "robot/clock/clock.h"
#include "robot/arm/head_arm_xarm.h"
#include "robot/head/head_loop.h"
#include "robot/link/link_server.h"
#include "robot/services/robot_control.h"
#include "robot/stereo/stereo_pairer.h"
#include "robot/telemetry/telemetry_batcher.h"
#include "robot/services/recording_switch.h"
#include "robot/video/video_streamer.h"

namespace telesphere::robot::services {

/// Where the health report reads from. Cameras, pairs and video may be absent (null).
struct RobotHealthSources {
  std::vector<const cameras::CameraSource*> cameras;  ///< [left, right]
  const stereo::StereoPairSource* pairs = nullptr;
  const video::VideoStreamer* video = nullptr;
  const head::HeadLoop* loop = nullptr;
  const RobotControl* control = nullptr;
  const link::LinkServer* server = nullptr;
  const telemetry::TelemetryBatcher* telemetry = nullptr;
  const RecordingSwitch* recording = nullptr;
  const arm::XArmHeadArm* xarm = nullptr;  ///< the real xArm's driver, when it is the arm (its figures)
  std::string arm;           ///< "simulated xArm 6", …
  std::string cameras_kind;  ///< "synthetic", "aravis", …
};

class RobotHealthReporter {
 public:
  RobotHealthReporter(RobotHealthSources sources, const clock::Clock& clock);

  /// The report as of now; camera fps over the time since the previous call.
  link::proto::RobotHealth make();

 private:
  RobotHealthSources sources_;
  const clock::Clock& clock_;
  std::int64_t started_ns_;
  std::int64_t last_ns_;
  std::vector<std::uint64_t> last_frames_;
};

}  // namespace telesphere::robot::services
