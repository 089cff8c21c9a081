// SPDX-License-Identifier: MIT
/// @brief The Internet link's media path as plotted series (DESIGN.md §9), for the console's link
///        panel. Qt-free.
///
/// From the robot, one sample per frame sent (SentFrame.media, at the frame's send time):
///   link.target_mbit     the send-rate controller's target, Mbit/s
///   link.delivered_mbit  what the receiver reported arriving (the estimate of the path), Mbit/s
///   link.cap_mbit        the supervisor's cap, Mbit/s (no sample while there is none)
///   link.rtt_ms          smoothed round trip of the media path, ms (none before it is measured)
///   link.queue_ms        one-way delay above the path's minimum, ms
///   link.loss_pct        datagrams lost before repair, %
///   link.fps             frame rate the stream is sent at, Hz
///   link.scale_pct       its scale per axis, %
///   link.quality         its JPEG quality
/// From the XR app's receiver, per telemetry batch (differences of its counts, at the batch time):
///   link.repaired_per_s  chunks rebuilt from parity, 1/s
///   link.concealed_per_s bands filled from the previous frame, 1/s
///   link.lost_frames_per_s frames given up, 1/s
/// The frame age is the image latency's capture → displayed (TelemetryModel).
#pragma once

#include <cstddef>
#include <optional>

#include "console/telemetry/series_store.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::telemetry {

namespace series {
inline constexpr const char* kLinkTargetMbit = "link.target_mbit";
inline constexpr const char* kLinkDeliveredMbit = "link.delivered_mbit";
inline constexpr const char* kLinkCapMbit = "link.cap_mbit";
inline constexpr const char* kLinkRttMs = "link.rtt_ms";
inline constexpr const char* kLinkQueueMs = "link.queue_ms";
inline constexpr const char* kLinkLossPct = "link.loss_pct";
inline constexpr const char* kLinkFps = "link.fps";
inline constexpr const char* kLinkScalePct = "link.scale_pct";
inline constexpr const char* kLinkQuality = "link.quality";
inline constexpr const char* kLinkRepairedPerS = "link.repaired_per_s";
inline constexpr const char* kLinkConcealedPerS = "link.concealed_per_s";
inline constexpr const char* kLinkLostFramesPerS = "link.lost_frames_per_s";
}  // namespace series

class MediaLinkSeries {
 public:
  /// Creates the twelve series (empty) in `store`.
  explicit MediaLinkSeries(SeriesStore& store);

  /// One frame's sample at `t` (plot clock, s); returns the samples appended.
  std::size_t addSentFrame(const link::proto::MediaLinkSample& sample, double t);
  /// The receiver's counts at `t`: rates since the previous counts (none for the first, nor
  /// after counts went backwards: a new receiver); returns the samples appended.
  std::size_t addReceiveCounts(const link::proto::MediaReceiveCounts& counts, double t);
  /// The XR app restarted: its counts start again.
  void receiverRestarted() { last_counts_.reset(); }

  /// Label and unit of a link.* series; nothing for another name.
  static std::optional<SeriesInfo> infoOf(const char* name);

 private:
  SeriesStore& store_;
  TimeSeries *target_, *delivered_, *cap_, *rtt_, *queue_, *loss_, *fps_, *scale_, *quality_;
  TimeSeries *repaired_, *concealed_, *lost_frames_;
  std::optional<std::pair<double, link::proto::MediaReceiveCounts>> last_counts_;
};

}  // namespace telesphere::console::telemetry
