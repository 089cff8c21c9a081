// SPDX-License-Identifier: MIT
/// @brief telesphere-robot --replay FILE: the link served from a recording (record::RecordingPlayer)
///        instead of a robot; control requests are answered with a refusal that says so, pings as
///        live; --record records the replay too.
#pragma once

#include <atomic>

#include "app/robot_options.h"

namespace telesphere::app {

/// Runs until the recording ends (never with --loop) or `stop`; the exit code: 0 served, 1 the
/// file cannot be read or is not a recording, 2 the link could not open, 3 damaged part way.
int runReplay(const RobotOptions& options, std::atomic<bool>& stop);

}  // namespace telesphere::app
