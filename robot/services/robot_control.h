// SPDX-License-Identifier: MIT
/// @brief The robot's answer to the link's control requests (DESIGN.md §7: every change through a
///        request with an explicit reply): JPEG quality and the media path's cap go to the video path, calibration stills
///        to the still taker, applying, reverting and reading the calibration to the calibration
///        in use, everything else to the head loop; every reply carries the robot's settings after the request, so the
///        console shows what is in force, never what it asked for.
#pragma once

#include <chrono>

#include "robot/head/calibration_in_use.h"
#include "robot/head/head_loop.h"
#include "robot/services/recording_switch.h"
#include "robot/link/telesphere_link.pb.h"
#include "robot/stereo/stereo_still.h"
#include "robot/video/video_streamer.h"

namespace telesphere::robot::services {

class RobotControl {
 public:
  /// The lowest media cap a supervisor may set (SendRateOptions::min_bps, the controller's floor).
  static constexpr double kMinMediaCapMbit = 0.5;
  /// How long a calibration still may take by default (a frame, then the joint state after it).
  static constexpr std::chrono::milliseconds kStillTimeout{800};

  /// `video`, `stills` and `calibration` may be null (no cameras, a fixed calibration): their
  /// requests are then refused. `still_timeout`: cameras slower than a frame within 800 ms of
  /// the request need more.
  /// `recording` (may be null: recording requests refused) also records study trials: a trial
  /// indicator that turns on with a recording name starts a recording, turning off stops it.
  RobotControl(head::HeadLoop& loop, video::VideoStreamer* video, stereo::StereoStillTaker* stills = nullptr,
               std::chrono::milliseconds still_timeout = kStillTimeout, head::CalibrationInUse* calibration = nullptr,
               RecordingSwitch* recording = nullptr)
      : loop_(loop),
        video_(video),
        stills_(stills),
        still_timeout_(still_timeout),
        calibration_(calibration),
        recording_(recording) {}

  link::proto::ControlReply handle(const link::proto::ControlRequest& request);
  void fillSettings(link::proto::RobotSettings* settings) const;

 private:
  /// Starts or stops the trial's recording after the head loop took a trial indicator.
  void followTrial(const link::proto::TrialIndicator& trial, link::proto::ControlReply* reply);

  head::HeadLoop& loop_;
  video::VideoStreamer* video_;
  stereo::StereoStillTaker* stills_;
  std::chrono::milliseconds still_timeout_;
  head::CalibrationInUse* calibration_;
  RecordingSwitch* recording_;
  bool trial_recording_ = false;  ///< the recording in progress was started by a trial indicator
};

}  // namespace telesphere::robot::services
