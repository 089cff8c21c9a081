// SPDX-License-Identifier: MIT
/// @brief RobotHealthReporter: the counters of every part, one message.
#include "robot/services/robot_health_reporter.h"

#include "robot/video/media_link_sample.h"

namespace telesphere::robot::services {
namespace {

void fillMediaHealth(const link::media::MediaSender& media, const video::VideoStreamerStats& video,
                     link::proto::MediaLinkHealth* out) {
  const link::media::MediaSenderStats s = media.stats();
  const bool receiver = !s.receiver_address.empty();
  *out->mutable_now() = video::mediaLinkSample(s, receiver, video.stream, video.stream.quality);
  out->set_port(media.port());
  out->set_receiver_address(s.receiver_address);
  out->set_frames_sent(s.frames_sent);
  out->set_frames_superseded(s.frames_superseded);
  out->set_datagrams_sent(s.datagrams_sent);
  out->set_bytes_sent(s.bytes_sent);
  out->set_reports_received(s.reports_received);
  out->set_receiver_changes(s.receiver_changes);
  out->set_head_target_datagrams(s.head_target_datagrams);
  out->set_sealed(s.sealed);
  out->set_datagrams_unauthenticated(s.unauthenticated);
  out->set_seal_sessions(s.seal_sessions);
  out->set_framing_overhead(s.framing_overhead);
  for (int d = 0; d < static_cast<int>(link::media::RateDecision::kCount); ++d) {
    if (s.rate.decisions[static_cast<std::size_t>(d)] == 0) continue;
    auto* count = out->add_rate_decisions();
    count->set_name(std::string(link::media::rateDecisionName(static_cast<link::media::RateDecision>(d))));
    count->set_count(s.rate.decisions[static_cast<std::size_t>(d)]);
  }
  for (int r = 0; r < static_cast<int>(video::StreamLimitedBy::kCount); ++r) {
    const std::uint64_t n = video.stream_decisions.decisions_by_reason[static_cast<std::size_t>(r)];
    if (n == 0) continue;
    auto* count = out->add_stream_decisions();
    count->set_name(video::streamLimitedByName(static_cast<video::StreamLimitedBy>(r)));
    count->set_count(n);
  }
}

}  // namespace

RobotHealthReporter::RobotHealthReporter(RobotHealthSources sources, const clock::Clock& clock)
    : sources_(std::move(sources)),
      clock_(clock),
      started_ns_(clock.nowNs()),
      last_ns_(started_ns_),
      last_frames_(sources_.cameras.size(), 0) {}

link::proto::RobotHealth RobotHealthReporter::make() {
  const std::int64_t now = clock_.nowNs();
  const double dt_s = double(now - last_ns_) * 1e-9;
  link::proto::RobotHealth h;
  h.set_t_ns(now);
  h.set_started_ns(started_ns_);
  h.set_arm(sources_.arm);
  h.set_cameras_kind(sources_.cameras_kind);
  if (sources_.recording != nullptr) *h.mutable_recording() = sources_.recording->state();
  if (sources_.server) {
    h.set_instance(sources_.server->instance());
    *h.mutable_trust() = sources_.server->trustHealth();
    const link::LinkStatsSnapshot link_stats = sources_.server->stats();
    for (int r = 0; r < static_cast<int>(link::DropReason::kCount); ++r) {
      if (link_stats.dropped_by_reason[r] == 0) continue;
      auto* count = h.add_link_drops();
      count->set_name(std::string(link::dropReasonName(static_cast<link::DropReason>(r))));
      count->set_count(link_stats.dropped_by_reason[r]);
    }
  }
  const video::VideoStreamerStats video = sources_.video ? sources_.video->stats() : video::VideoStreamerStats{};
  const stereo::StereoPairerStats pairs = sources_.pairs ? sources_.pairs->stats() : stereo::StereoPairerStats{};
  for (std::size_t i = 0; i < sources_.cameras.size(); ++i) {
    const cameras::CameraSource* camera = sources_.cameras[i];
    const cameras::CameraStats stats = camera->stats();
    auto* c = h.add_cameras();
    c->set_name(camera->name());
    c->set_fps(dt_s > 0 ? double(stats.frames - last_frames_[i]) / dt_s : 0.0);
    c->set_frames(stats.frames);
    c->set_incomplete(stats.incomplete);
    c->set_lost(stats.lost);
    c->set_reconnects(stats.reconnects);
    c->set_last_error(stats.last_error);
    if (i < 2) {
      c->set_unpaired(pairs.dropped[i].total());
      c->set_exposure_us(video.exposure_us_last[i]);
    }
    c->set_width(static_cast<std::uint32_t>(video.width));
    c->set_height(static_cast<std::uint32_t>(video.height));
    last_frames_[i] = stats.frames;
  }
  h.set_pairs(pairs.pairs);
  if (sources_.pairs) h.set_pairs_dropped_queue(sources_.pairs->pairsDropped());
  h.set_frames_sent(video.frames_sent);
  h.set_encode_failures(video.encode_failures);
  h.set_encode_ms_last(video.encode_ms_last);
  if (const link::media::MediaSender* media = sources_.video ? sources_.video->mediaSender() : nullptr)
    fillMediaHealth(*media, video, h.mutable_media());
  if (sources_.loop) sources_.loop->fillHealth(&h);
  if (sources_.xarm) {
    const arm::XArmHeadArm::Stats x = sources_.xarm->stats();
    auto* out = h.mutable_xarm();
    out->set_firmware(x.firmware);
    out->set_serial(x.serial);
    out->set_protocol(x.protocol);
    out->set_link_delay_ms(x.link_delay_ms);
    out->set_report_jitter_ms_p99(x.report_jitter_ms_p99);
    out->set_report_drift_ppm(x.report_drift_ppm);
    out->set_reports(x.reports);
    out->set_targets_sent(x.targets_sent);
    out->set_refused_jumps(x.refused_jumps);
    out->set_refused_limits(x.refused_limits);
    out->set_reconnects(x.reconnects);
    out->set_payload_read(x.payload_read);
    out->set_payload_kg(x.payload_kg);
    out->set_payload_com_x_mm(x.payload_com_mm[0]);
    out->set_payload_com_y_mm(x.payload_com_mm[1]);
    out->set_payload_com_z_mm(x.payload_com_mm[2]);
    out->set_collision_sensitivity(x.collision_sensitivity);
    out->set_readback_error(x.readback_error);
  }
  if (sources_.control) sources_.control->fillSettings(h.mutable_settings());
  if (sources_.telemetry) {
    h.set_telemetry_batches(sources_.telemetry->batches());
    h.set_telemetry_samples_dropped(sources_.telemetry->droppedSamples());
  }
  last_ns_ = now;
  return h;
}

}  // namespace telesphere::robot::services
