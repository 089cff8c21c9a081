// SPDX-License-Identifier: MIT
/// @brief Headset sessions one after another around the operator loop (DESIGN.md §2): a session
///        is created on the current GL context, its events are handled, frames run through the
///        OperatorLoop over an OpenXrOutput while the runtime syncs frames, an exit is asked for
///        after `frames` submitted frames or when `stop` is set (and the session destroyed when
///        the runtime does not end it within exit_timeout_s); when the runtime goes away, it is
///        waited for up to reconnect_s and a new session starts. Progress lines (session start,
///        runtime loss, interruption) go to `notes`, in the words the command prints.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "xr/openxr/openxr_output.h"
#include "xr/openxr/openxr_session.h"
#include "xr/frame_loop/operator_loop.h"

namespace telesphere::xr::openxr {

struct OpenXrRunOptions {
  OpenXrOptions session;
  std::uint64_t frames = 0;     ///< ask to exit after this many submitted frames (0: until stop)
  double exit_timeout_s = 5.0;  ///< then destroy a session the runtime did not end
  double reconnect_s = 30.0;    ///< wait this long for a runtime that went away (0: do not)
};

struct OpenXrRunHooks {
  /// Between frames (also while no frame is due): false asks to exit (a mirror window closed).
  std::function<bool()> between_frames;
  /// A controller's "capture the nominal pose" button was pressed.
  std::function<void()> capture_nominal;
  /// A session started (its number from 1).
  std::function<void(const OpenXrSession&, int session)> session_started;
  /// A progress line for the operator (stdout: `error` false; stderr: true).
  std::function<void(const std::string& line, bool error)> note;
};

enum class OpenXrRunEnd {
  kFinished,     ///< the last session ended normally (frames done, stop, the runtime stopped it)
  kFailed,       ///< an OpenXR call or the loop failed
  kRuntimeGone,  ///< the runtime went away and did not come back within reconnect_s
  kNoRuntime,    ///< no runtime at the start
};

struct OpenXrRunResult {
  OpenXrRunEnd end = OpenXrRunEnd::kFinished;
  std::string error;  ///< why, unless finished
  int sessions = 0;
  std::uint64_t waited = 0, submitted = 0;  ///< frames xrWaitFrame'd, and submitted with a layer
  std::uint64_t not_rendered = 0;           ///< waited but ended without layers
  bool focused_ever = false;
  double fps = 0;       ///< submitted frames per second from the first submitted one
  std::string states;   ///< each session's state history, " | " between sessions
};

/// Runs sessions until finished; needs the GL context the output's frames render with current.
OpenXrRunResult runOpenXrSessions(OpenXrOutput& output, frame_loop::OperatorLoop& loop, const OpenXrRunOptions& options,
                                  const OpenXrRunHooks& hooks, const std::atomic<bool>& stop);

}  // namespace telesphere::xr::openxr
