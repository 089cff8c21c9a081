// SPDX-License-Identifier: MIT
/// @brief The media path's state in the link's words (DESIGN.md §9): the send-rate controller's
///        target, what arrived, the cap, round trip, queue and loss, and the stream settings the
///        video path chose for that rate. The console's link panel plots one per frame sent
///        (SentFrame.media) and shows the newest in the robot's health.
#pragma once

#include "robot/link/media/media_sender.h"
#include "robot/link/telesphere_link.pb.h"
#include "robot/video/stream_settings_controller.h"

namespace telesphere::robot::video {

/// `quality`: the JPEG quality the frame was encoded at (the stream's, or the nominal one when
/// the stream is not adapted).
link::proto::MediaLinkSample mediaLinkSample(const link::media::MediaSenderStats& sender, bool receiver,
                                             const StreamSettings& stream, int quality);

}  // namespace telesphere::robot::video
