// SPDX-License-Identifier: MIT
/// @brief runOpenXrSessions: one session's event and frame loop, then reconnect or end.
#include "xr/openxr/openxr_run.h"

#include <sstream>
#include <thread>

namespace telesphere::xr::openxr {
namespace {

using Clock = std::chrono::steady_clock;

std::string stateHistory(const SessionStateMachine& machine) {
  std::string text;
  for (const SessionState s : machine.history()) {
    if (!text.empty()) text.append(" ");
    text.append(sessionStateName(s));
  }
  return text.empty() ? "(none)" : text;
}

/// Seconds as the operator reads them: "30", "2.5".
std::string seconds(double s) {
  std::ostringstream os;
  os << s;
  return os.str();
}

enum class SessionEnd { kFinished, kLost, kFailed };

struct RunState {
  OpenXrRunResult& result;
  const OpenXrRunOptions& options;
  const OpenXrRunHooks& hooks;
  const std::atomic<bool>& stop;
  bool quit_asked = false;  ///< by the operator between frames: no reconnect either
  std::optional<Clock::time_point> first_submitted, last_submitted;

  void note(const std::string& line, bool error) const {
    if (hooks.note) hooks.note(line, error);
  }
};

/// Runs one session until it ends; the reason in result.error when it failed.
SessionEnd runSession(OpenXrSession& session, OpenXrOutput& output, frame_loop::OperatorLoop& loop, RunState& run) {
  std::string error;
  std::optional<Clock::time_point> exit_asked;
  output.setSession(&session);
  loop.outputRestarted();
  while (true) {
    if (run.hooks.between_frames && !run.hooks.between_frames()) run.quit_asked = true;
    const bool interrupted = run.quit_asked || run.stop.load();
    const bool want_exit = interrupted || (run.options.frames > 0 && run.result.submitted >= run.options.frames);
    if (want_exit && !exit_asked) {
      if (interrupted) run.note("interrupted: ending the session", false);
      exit_asked = Clock::now();
      if (!session.requestExit(&error) && !session.lost()) {
        run.result.error = error;
        return SessionEnd::kFailed;
      }
    }
    if (exit_asked && Clock::now() - *exit_asked > std::chrono::duration<double>(run.options.exit_timeout_s)) {
      run.note("the runtime did not end the session within " + seconds(run.options.exit_timeout_s) +
                   " s of xrRequestExitSession; destroying it",
               true);
      return SessionEnd::kFinished;
    }
    if (!session.pollEvents(&error) && !session.lost()) {
      run.result.error = error;
      return SessionEnd::kFailed;
    }
    if (session.state().reached(SessionState::kFocused)) run.result.focused_ever = true;
    if (session.lost()) {
      run.note("the OpenXR runtime went away during the session (" +
                   (error.empty() ? std::string("instance loss pending") : error) + ")",
               true);
      return SessionEnd::kLost;
    }
    if (session.state().finished()) return SessionEnd::kFinished;
    if (!session.state().shouldSyncFrames()) {
      // Not running yet (or no longer): events arrive without frames; poll at 100 Hz.
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    if (!loop.step(&error)) {
      if (session.lost()) {
        run.note("the OpenXR runtime went away during the session (" + error + ")", true);
        return SessionEnd::kLost;
      }
      run.result.error = error;
      return SessionEnd::kFailed;
    }
    const frame_loop::OperatorOutput::Shown& shown = loop.last();
    if (shown.began) ++run.result.waited;
    if (shown.drawn) {
      ++run.result.submitted;
      run.last_submitted = Clock::now();
      if (!run.first_submitted) run.first_submitted = run.last_submitted;
    } else if (shown.began) {
      ++run.result.not_rendered;
    }
    if (output.lastResult().capture_nominal_pressed && run.hooks.capture_nominal) run.hooks.capture_nominal();
  }
}

}  // namespace

OpenXrRunResult runOpenXrSessions(OpenXrOutput& output, frame_loop::OperatorLoop& loop, const OpenXrRunOptions& options,
                                  const OpenXrRunHooks& hooks, const std::atomic<bool>& stop) {
  OpenXrRunResult result;
  RunState run{result, options, hooks, stop, false, {}, {}};
  std::optional<Clock::time_point> reconnect_until;
  while (!stop.load() && !run.quit_asked) {
    std::string error;
    OpenXrFailure failure = OpenXrFailure::kNone;
    auto session = OpenXrSession::create(options.session, &error, &failure);
    if (!session) {
      if (reconnect_until && failure == OpenXrFailure::kNoRuntime) {
        if (Clock::now() < *reconnect_until) {
          std::this_thread::sleep_for(std::chrono::milliseconds(500));
          continue;
        }
        result.end = OpenXrRunEnd::kRuntimeGone;
        result.error = "the OpenXR runtime did not come back within " + seconds(options.reconnect_s) +
                       " s; start it again and rerun";
        break;
      }
      result.end = failure == OpenXrFailure::kNoRuntime ? OpenXrRunEnd::kNoRuntime : OpenXrRunEnd::kFailed;
      result.error = error;
      break;
    }
    reconnect_until.reset();
    ++result.sessions;
    if (hooks.session_started) hooks.session_started(*session, result.sessions);
    const SessionEnd end = runSession(*session, output, loop, run);
    if (!result.states.empty()) result.states += " | ";
    result.states += stateHistory(session->state());
    output.setSession(nullptr);
    session.reset();
    if (end == SessionEnd::kFailed) {
      result.end = OpenXrRunEnd::kFailed;
      break;
    }
    if (end == SessionEnd::kFinished) break;
    // Lost: wait for the runtime to come back, or give up.
    if (options.reconnect_s <= 0.0 || stop.load() || run.quit_asked) {
      result.end = OpenXrRunEnd::kRuntimeGone;
      result.error = "the OpenXR runtime went away during the session; start the runtime again and rerun";
      break;
    }
    run.note("the OpenXR runtime went away; waiting up to " + seconds(options.reconnect_s) +
                 " s for it to come back",
             false);
    reconnect_until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>(options.reconnect_s));
  }
  const double seconds =
      run.first_submitted ? std::chrono::duration<double>(*run.last_submitted - *run.first_submitted).count() : 0.0;
  result.fps = seconds > 0 ? double(result.submitted - 1) / seconds : 0.0;
  return result;
}

}  // namespace telesphere::xr::openxr
