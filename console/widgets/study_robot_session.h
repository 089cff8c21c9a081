// SPDX-License-Identifier: MIT
/// @brief The study's robot (study::StudyRobot) over the console's link session: control
///        requests through ConsoleSession (replies on the GUI thread), the XR app's mode from the
///        telemetry it relays, the robot's process from the pongs.
#pragma once

#include "console/study/study_robot.h"

namespace telesphere::console {

class ConsoleSession;

class StudyRobotSession final : public study::StudyRobot {
 public:
  explicit StudyRobotSession(ConsoleSession& session) : session_(session) {}

  void requestMode(link::proto::VisualMode mode, std::function<void(const Reply&)> done) override;
  void sendTrialIndicator(const link::proto::TrialIndicator& indicator, std::function<void(const Reply&)> done) override;
  std::optional<link::proto::VisualMode> xrVisualMode() const override;
  std::uint64_t robotInstance() const override;

 private:
  ConsoleSession& session_;
};

}  // namespace telesphere::console
