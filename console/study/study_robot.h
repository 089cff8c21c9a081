// SPDX-License-Identifier: MIT
/// @brief What a study needs of the robot (and, through it, the XR app): the trial's visual mode
///        switched and confirmed, the trial indicator (with the trial's recording), and whether
///        the robot or the XR app are there. The console's link session implements it
///        (console/widgets/study_robot_session.h); tests script it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::study {

class StudyRobot {
 public:
  /// The robot's answer to a request.
  struct Reply {
    bool answered = false;  ///< false: no reply within the request's timeout
    bool ok = false;
    std::string error;  ///< the robot's words (refused, or ok with a remark: "the trial runs, but is not recorded: …")
    link::proto::RecordingState recording;  ///< what the robot records after a trial indicator
  };

  virtual ~StudyRobot() = default;
  /// Asks the robot for `mode`; `done` later (on the caller's thread), once.
  virtual void requestMode(link::proto::VisualMode mode, std::function<void(const Reply&)> done) = 0;
  /// Sends the trial indicator (and with it the trial's recording name); `done` later, once.
  virtual void sendTrialIndicator(const link::proto::TrialIndicator& indicator, std::function<void(const Reply&)> done) = 0;
  /// What the XR app renders with now; nothing when the XR app is not connected.
  virtual std::optional<link::proto::VisualMode> xrVisualMode() const = 0;
  /// The robot process that answers now (0: none yet); a new value means it restarted.
  virtual std::uint64_t robotInstance() const = 0;
};

}  // namespace telesphere::console::study
