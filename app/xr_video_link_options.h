// SPDX-License-Identifier: MIT
/// @brief How the operator app takes its frames and sends its head targets, the same options for
///        `telesphere-xr offscreen`, `openxr` and `desktop`: the ZeroMQ link, or the UDP media path
///        (DESIGN.md §9; robot/link/media) that holds up across the Internet.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "app/link_security_options.h"
#include "xr/frame_loop/operator_view.h"

namespace telesphere::app {

struct VideoLinkOptions {
  std::string video_link = "zmq";   ///< zmq: the ZeroMQ link; udp: the media path (port + 4)
  int media_port = 0;               ///< the media path's UDP port when not port + 4 (a relay's)
  std::string media_repair = "on";  ///< on | off: retransmission of what parity cannot rebuild
  std::string head_link = "both";   ///< with --video-link udp: head targets on both links, or udp only
  LinkSecurityOptions security;     ///< --keys DIR (an operator key and the robot's .pub) | --insecure
  link::trust::LinkCredentials credentials;  ///< read by checkVideoLinkOptions
};

/// --video-link, --media-port, --media-repair, --head-link on `command`.
void addVideoLinkOptions(CLI::App& command, VideoLinkOptions& options);
/// Reads the credentials --keys names (an operator key); false, with the reason, without --keys or
/// --insecure, and for a folder that is not usable.
bool checkVideoLinkOptions(VideoLinkOptions& options, std::string* error);
/// The options into the operator view's.
void applyVideoLinkOptions(const VideoLinkOptions& options, xr::frame_loop::OperatorViewOptions& view);

}  // namespace telesphere::app
