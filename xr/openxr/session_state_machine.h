// SPDX-License-Identifier: MIT
/// @brief The OpenXR session life cycle as pure logic (no runtime calls), so that every
///        transition is unit-tested without a runtime: which call the app must make when the
///        runtime reports a state (xrBeginSession on READY, xrEndSession on STOPPING, tear down
///        on LOSS_PENDING or EXITING), whether frames are to be synchronised (xrWaitFrame …
///        xrEndFrame) and rendered, and what an exit request (SIGINT) or instance loss does.
///
/// The OpenXR 1.0 life cycle: IDLE → READY → (xrBeginSession) → SYNCHRONIZED → VISIBLE →
/// FOCUSED → … → STOPPING → (xrEndSession) → IDLE → EXITING or LOSS_PENDING. Frames are waited
/// for and submitted while the session is running (after xrBeginSession succeeded, until
/// xrEndSession); layers are only worth rendering when VISIBLE or FOCUSED (otherwise the frame is
/// ended with no layers).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace telesphere::xr::openxr {

/// XrSessionState, plus kUnknown for values this code does not know.
enum class SessionState : std::uint8_t {
  kUnknown,
  kIdle,
  kReady,
  kSynchronized,
  kVisible,
  kFocused,
  kStopping,
  kLossPending,
  kExiting,
};

/// "IDLE", "READY", …, "UNKNOWN" (the XR_SESSION_STATE_ suffix).
std::string_view sessionStateName(SessionState state);

/// Maps an XrSessionState value (XR_SESSION_STATE_IDLE = 1 … XR_SESSION_STATE_EXITING = 8).
SessionState sessionStateFromXr(int xr_session_state);

/// What the owner of the session has to do after feeding the machine an event.
enum class SessionAction : std::uint8_t {
  kNone,
  kBeginSession,     ///< call xrBeginSession, then onSessionBegun() (or onSessionBeginFailed())
  kEndSession,       ///< call xrEndSession, then onSessionEnded()
  kRequestExit,      ///< call xrRequestExitSession; the runtime then goes STOPPING → … → EXITING
  kDestroySession,   ///< destroy the session (EXITING): the run is over
  kRecreateSession,  ///< the session (LOSS_PENDING) or instance is lost: tear down; try again later
};

std::string_view sessionActionName(SessionAction action);

class SessionStateMachine {
 public:
  /// XrEventDataSessionStateChanged: the runtime moved the session to `state`.
  SessionAction onStateChanged(SessionState state);
  /// xrBeginSession succeeded / failed.
  void onSessionBegun();
  void onSessionBeginFailed();
  /// xrEndSession was called (whatever it returned, the session no longer runs).
  void onSessionEnded();
  /// XrEventDataInstanceLossPending, or a call returned XR_ERROR_INSTANCE_LOST or
  /// XR_ERROR_SESSION_LOST: nothing more can be done with the session. Ignored (kNone) once
  /// the session has finished.
  SessionAction onLost();
  /// The user wants to quit (SIGINT, --frames reached). Running: kRequestExit (the runtime ends
  /// the session; frames continue until STOPPING); not running: kDestroySession. Repeated
  /// requests return kNone.
  SessionAction requestExit();

  SessionState state() const { return state_; }
  /// Between xrBeginSession and xrEndSession: frames must be waited for and ended.
  bool running() const { return running_; }
  /// Running (from xrBeginSession on, READY included: the runtime only moves to SYNCHRONIZED
  /// once frames are waited for) and not finished: call xrWaitFrame, xrBeginFrame, xrEndFrame.
  bool shouldSyncFrames() const;
  /// VISIBLE or FOCUSED (and running): the frame's layers are shown, so render them.
  bool shouldRender() const;
  /// The loop is over: EXITING reached, the session was lost, or an exit was requested while
  /// not running.
  bool finished() const { return finished_; }
  bool lost() const { return lost_; }
  bool exitRequested() const { return exit_requested_; }
  /// Every state reported by the runtime, in order (repeats of the same state collapsed).
  const std::vector<SessionState>& history() const { return history_; }
  /// True when `state` has been reported at least once.
  bool reached(SessionState state) const;

 private:
  SessionState state_ = SessionState::kUnknown;
  bool running_ = false;
  bool finished_ = false;
  bool lost_ = false;
  bool exit_requested_ = false;
  std::vector<SessionState> history_;
};

}  // namespace telesphere::xr::openxr
