// SPDX-License-Identifier: MIT
/// @brief addVideoLinkOptions, applyVideoLinkOptions (see xr_video_link_options.h).
#include "app/xr_video_link_options.h"

namespace telesphere::app {

void addVideoLinkOptions(CLI::App& c, VideoLinkOptions& o) {
  c.add_option("--video-link", o.video_link,
               "how frames come: zmq (the ZeroMQ link, port) or udp (the paced media path, port+4, lost bands "
               "painted from the previous frame; across the Internet)")
      ->capture_default_str()->check(CLI::IsMember({"zmq", "udp"}));
  c.add_option("--media-port", o.media_port,
               "--video-link udp: the media path's UDP port (default port+4; a relay's port to test a path)")
      ->check(CLI::Range(1, 65535));
  c.add_option("--media-repair", o.media_repair,
               "--video-link udp: ask the robot again for the chunks of the newest frame its parity cannot "
               "rebuild (on), or show them concealed at once (off)")
      ->capture_default_str()->check(CLI::IsMember({"on", "off"}));
  c.add_option("--head-link", o.head_link,
               "--video-link udp: head targets on both links (the robot keeps the newest) or on udp only")
      ->capture_default_str()->check(CLI::IsMember({"both", "udp"}));
  addLinkSecurityOptions(c, o.security, "this operator's key pair (role operator) and the robot's .pub");
}

bool checkVideoLinkOptions(VideoLinkOptions& o, std::string* error) {
  auto credentials = linkCredentialsFrom(o.security, {link::trust::LinkRole::kOperator}, error);
  if (!credentials) return false;
  o.credentials = std::move(*credentials);
  return true;
}

void applyVideoLinkOptions(const VideoLinkOptions& o, xr::frame_loop::OperatorViewOptions& view) {
  view.endpoints.credentials = o.credentials;
  view.warn_insecure_link = o.security.insecure;
  view.media_link = o.video_link == "udp";
  view.media_port = o.media_port;
  view.media_repair = o.media_repair == "on";
  view.head_targets_on_zmq = o.head_link == "both";
}

}  // namespace telesphere::app
