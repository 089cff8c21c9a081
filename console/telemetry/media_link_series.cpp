// SPDX-License-Identifier: MIT
/// @brief MediaLinkSeries: media path samples and receiver counts → series.
#include "console/telemetry/media_link_series.h"

#include <cstring>
#include <utility>

namespace telesphere::console::telemetry {
namespace {

constexpr double kSentGapS = 1.0;      ///< frames at ≥ 1 Hz join up (the stream's floor is 5 Hz)
constexpr double kCountsGapS = 1.0;    ///< the XR app's batches come every 100 ms

}  // namespace

std::optional<SeriesInfo> MediaLinkSeries::infoOf(const char* name) {
  static const struct {
    const char* name;
    const char* label;
    const char* unit;
  } kInfo[] = {
      {series::kLinkTargetMbit, "media path target", "Mbit/s"},
      {series::kLinkDeliveredMbit, "media path delivered (estimate)", "Mbit/s"},
      {series::kLinkCapMbit, "supervisor's cap", "Mbit/s"},
      {series::kLinkRttMs, "media path round trip", "ms"},
      {series::kLinkQueueMs, "queuing delay", "ms"},
      {series::kLinkLossPct, "datagram loss before repair", "%"},
      {series::kLinkFps, "stream frame rate", "Hz"},
      {series::kLinkScalePct, "stream scale per axis", "%"},
      {series::kLinkQuality, "stream JPEG quality", ""},
      {series::kLinkRepairedPerS, "chunks repaired (FEC)", "1/s"},
      {series::kLinkConcealedPerS, "bands concealed", "1/s"},
      {series::kLinkLostFramesPerS, "frames lost", "1/s"},
  };
  for (const auto& i : kInfo)
    if (std::strcmp(i.name, name) == 0) return SeriesInfo{i.name, i.label, i.unit};
  return std::nullopt;
}

MediaLinkSeries::MediaLinkSeries(SeriesStore& store) : store_(store) {
  const auto make = [&](const char* name, double gap_s) { return &store_.series(*infoOf(name), gap_s); };
  target_ = make(series::kLinkTargetMbit, kSentGapS);
  delivered_ = make(series::kLinkDeliveredMbit, kSentGapS);
  cap_ = make(series::kLinkCapMbit, kSentGapS);
  rtt_ = make(series::kLinkRttMs, kSentGapS);
  queue_ = make(series::kLinkQueueMs, kSentGapS);
  loss_ = make(series::kLinkLossPct, kSentGapS);
  fps_ = make(series::kLinkFps, kSentGapS);
  scale_ = make(series::kLinkScalePct, kSentGapS);
  quality_ = make(series::kLinkQuality, kSentGapS);
  repaired_ = make(series::kLinkRepairedPerS, kCountsGapS);
  concealed_ = make(series::kLinkConcealedPerS, kCountsGapS);
  lost_frames_ = make(series::kLinkLostFramesPerS, kCountsGapS);
}

std::size_t MediaLinkSeries::addSentFrame(const link::proto::MediaLinkSample& s, double t) {
  std::size_t n = 0;
  const auto add = [&](TimeSeries* series, double v) {
    series->append(t, v);
    ++n;
  };
  // Without a receiver nothing goes out: the controller's figures would be from nobody.
  if (s.receiver()) {
    add(target_, s.target_mbit());
    add(delivered_, s.delivered_mbit());
    if (s.rtt_ms() >= 0) add(rtt_, s.rtt_ms());
    add(queue_, s.queue_delay_ms());
    add(loss_, s.loss_fraction() * 100.0);
  }
  if (s.cap_mbit() > 0) add(cap_, s.cap_mbit());
  add(fps_, s.fps());
  add(scale_, s.scale() * 100.0);
  add(quality_, double(s.quality()));
  return n;
}

std::size_t MediaLinkSeries::addReceiveCounts(const link::proto::MediaReceiveCounts& c, double t) {
  std::size_t n = 0;
  if (last_counts_) {
    const auto& [t0, p] = *last_counts_;
    const double dt = t - t0;
    const bool backwards = c.datagrams() < p.datagrams() || c.chunks_repaired() < p.chunks_repaired() ||
                           c.bands_concealed() < p.bands_concealed() || c.frames_lost() < p.frames_lost();
    if (backwards) {
      last_counts_.reset();
    } else if (dt > 0) {
      repaired_->append(t, double(c.chunks_repaired() - p.chunks_repaired()) / dt);
      concealed_->append(t, double(c.bands_concealed() - p.bands_concealed()) / dt);
      lost_frames_->append(t, double(c.frames_lost() - p.frames_lost()) / dt);
      n = 3;
    }
  }
  if (!last_counts_ || t > last_counts_->first) last_counts_ = std::make_pair(t, c);
  return n;
}

}  // namespace telesphere::console::telemetry
