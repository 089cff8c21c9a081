// SPDX-License-Identifier: MIT
/// @brief StudyRobotSession (see study_robot_session.h).
#include "console/widgets/study_robot_session.h"

#include "console/widgets/console_session.h"
#include "robot/link/proto_enums.h"
#include "robot/link/visual_mode.h"

namespace telesphere::console {
namespace {

study::StudyRobot::Reply replyOf(const ControlOutcome& outcome) {
  study::StudyRobot::Reply r;
  r.answered = outcome.answered;
  r.ok = outcome.ok;
  r.error = outcome.ok ? outcome.reply.error() : outcome.error.toStdString();
  r.recording = outcome.reply.recording();
  return r;
}

}  // namespace

void StudyRobotSession::requestMode(link::proto::VisualMode mode, std::function<void(const Reply&)> done) {
  link::proto::ControlRequest request;
  request.set_set_visual_mode(mode);
  const auto m = link::fromProto(mode);
  session_.request(request, "study: set_visual_mode " + QString::fromStdString(m ? std::string(link::visualModeName(*m)) : "?"),
                   [done = std::move(done)](const ControlOutcome& outcome) { done(replyOf(outcome)); });
}

void StudyRobotSession::sendTrialIndicator(const link::proto::TrialIndicator& indicator,
                                           std::function<void(const Reply&)> done) {
  link::proto::ControlRequest request;
  *request.mutable_set_trial_indicator() = indicator;
  session_.request(request, indicator.running() ? "study: trial indicator on" : "study: trial indicator off",
                   [done = std::move(done)](const ControlOutcome& outcome) { done(replyOf(outcome)); });
}

std::optional<link::proto::VisualMode> StudyRobotSession::xrVisualMode() const {
  if (session_.xr().state() != supervision::PeerState::kConnected) return std::nullopt;
  return session_.telemetry().xrVisualMode();
}

std::uint64_t StudyRobotSession::robotInstance() const {
  return session_.robot().state() == supervision::PeerState::kConnected ? session_.activity().robot_instance : 0;
}

}  // namespace telesphere::console
