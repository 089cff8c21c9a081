// SPDX-License-Identifier: MIT
/// @brief mediaLinkSample: sender statistics and stream settings → proto.
#include "robot/video/media_link_sample.h"

namespace telesphere::robot::video {

link::proto::MediaLinkSample mediaLinkSample(const link::media::MediaSenderStats& sender, bool receiver,
                                             const StreamSettings& stream, int quality) {
  link::proto::MediaLinkSample s;
  s.set_receiver(receiver);
  s.set_target_mbit(sender.rate.target_bps * 1e-6);
  s.set_delivered_mbit(sender.rate.delivered_bps * 1e-6);
  s.set_cap_mbit(sender.cap_bps * 1e-6);
  s.set_rtt_ms(sender.rate.rtt_ms);
  s.set_queue_delay_ms(sender.rate.queue_delay_ms);
  s.set_loss_fraction(sender.rate.loss_fraction);
  s.set_fps(stream.fps);
  s.set_scale(stream.scale);
  s.set_quality(static_cast<std::uint32_t>(quality));
  s.set_limited_by(streamLimitedByName(stream.limited_by));
  return s;
}

}  // namespace telesphere::robot::video
