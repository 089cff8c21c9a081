// SPDX-License-Identifier: MIT
/// @brief SessionStateMachine: OpenXR session states → the calls the app has to make.
#include "xr/openxr/session_state_machine.h"

#include <algorithm>

namespace telesphere::xr::openxr {

std::string_view sessionStateName(SessionState state) {
  switch (state) {
    case SessionState::kIdle: return "IDLE";
    case SessionState::kReady: return "READY";
    case SessionState::kSynchronized: return "SYNCHRONIZED";
    case SessionState::kVisible: return "VISIBLE";
    case SessionState::kFocused: return "FOCUSED";
    case SessionState::kStopping: return "STOPPING";
    case SessionState::kLossPending: return "LOSS_PENDING";
    case SessionState::kExiting: return "EXITING";
    case SessionState::kUnknown: break;
  }
  return "UNKNOWN";
}

SessionState sessionStateFromXr(int xr_session_state) {
  switch (xr_session_state) {
    case 1: return SessionState::kIdle;
    case 2: return SessionState::kReady;
    case 3: return SessionState::kSynchronized;
    case 4: return SessionState::kVisible;
    case 5: return SessionState::kFocused;
    case 6: return SessionState::kStopping;
    case 7: return SessionState::kLossPending;
    case 8: return SessionState::kExiting;
    default: return SessionState::kUnknown;
  }
}

std::string_view sessionActionName(SessionAction action) {
  switch (action) {
    case SessionAction::kNone: return "none";
    case SessionAction::kBeginSession: return "begin session";
    case SessionAction::kEndSession: return "end session";
    case SessionAction::kRequestExit: return "request exit";
    case SessionAction::kDestroySession: return "destroy session";
    case SessionAction::kRecreateSession: return "recreate session";
  }
  return "?";
}

SessionAction SessionStateMachine::onStateChanged(SessionState state) {
  if (history_.empty() || history_.back() != state) history_.push_back(state);
  state_ = state;
  if (finished_) return SessionAction::kNone;
  switch (state) {
    case SessionState::kReady:
      // A READY after an exit request is not followed: the user wants out.
      if (exit_requested_) {
        finished_ = true;
        return SessionAction::kDestroySession;
      }
      return running_ ? SessionAction::kNone : SessionAction::kBeginSession;
    case SessionState::kStopping:
      return running_ ? SessionAction::kEndSession : SessionAction::kNone;
    case SessionState::kExiting:
      finished_ = true;
      return SessionAction::kDestroySession;
    case SessionState::kLossPending:
      return onLost();
    case SessionState::kIdle:
      // An exit was asked for and the runtime has ended the session: nothing more will come
      // but EXITING, which some runtimes skip when the app asked; finish on IDLE too.
      if (exit_requested_ && !running_) {
        finished_ = true;
        return SessionAction::kDestroySession;
      }
      return SessionAction::kNone;
    case SessionState::kSynchronized:
    case SessionState::kVisible:
    case SessionState::kFocused:
    case SessionState::kUnknown:
      break;
  }
  return SessionAction::kNone;
}

void SessionStateMachine::onSessionBegun() { running_ = true; }

void SessionStateMachine::onSessionBeginFailed() { running_ = false; }

void SessionStateMachine::onSessionEnded() { running_ = false; }

SessionAction SessionStateMachine::onLost() {
  // Already over (EXITING reached, or lost before): nothing left to lose.
  if (lost_ || finished_) return SessionAction::kNone;
  lost_ = true;
  finished_ = true;
  running_ = false;
  return SessionAction::kRecreateSession;
}

SessionAction SessionStateMachine::requestExit() {
  if (exit_requested_ || finished_) return SessionAction::kNone;
  exit_requested_ = true;
  if (running_) return SessionAction::kRequestExit;
  finished_ = true;
  return SessionAction::kDestroySession;
}

bool SessionStateMachine::shouldSyncFrames() const {
  // From xrBeginSession on (still READY): the runtime only reports SYNCHRONIZED once the app
  // waits for frames.
  return running_ && !finished_;
}

bool SessionStateMachine::shouldRender() const {
  return shouldSyncFrames() &&
         (state_ == SessionState::kVisible || state_ == SessionState::kFocused);
}

bool SessionStateMachine::reached(SessionState state) const {
  return std::find(history_.begin(), history_.end(), state) != history_.end();
}

}  // namespace telesphere::xr::openxr
