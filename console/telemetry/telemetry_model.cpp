// SPDX-License-Identifier: MIT
/// @brief TelemetryModel: source stamps → one clock → series.
#include "console/telemetry/telemetry_model.h"

#include <cstring>

#include "robot/link/link_pose.h"

namespace telesphere::console::telemetry {
namespace {

constexpr double kFrameGapS = 1.0;  ///< frames at ≥ 1 Hz join up; a longer silence is a gap
constexpr double kTickGapS = 0.5;   ///< 100 Hz ticks
/// Speeds from poses further apart than this are not computed (a gap, not a motion).
constexpr std::int64_t kMaxSpeedGapNs = 200'000'000;

Eigen::Vector3d positionOf(const link::proto::Pose& p) { return {p.tx(), p.ty(), p.tz()}; }

}  // namespace

TelemetryModel::TelemetryModel(SeriesStore& store, std::int64_t origin_console_ns)
    : store_(store), origin_ns_(origin_console_ns), link_(store), depth_(store) {
  for (int i = 0; i < 6; ++i) stages_[i] = &store_.series(infoOf(series::kLatencyStages[i]), kFrameGapS);
  head_latency_ = &store_.series(infoOf(series::kHeadLatency), kTickGapS);
  v_op_ = &store_.series(infoOf(series::kVOp), kFrameGapS);
  v_rob_ = &store_.series(infoOf(series::kVRob), kTickGapS);
  delta_s_ = &store_.series(infoOf(series::kDeltaS), kFrameGapS);
  frame_ms_ = &store_.series(infoOf(series::kXrFrameMs), kFrameGapS);
  missed_ = &store_.series(infoOf(series::kXrMissed), kFrameGapS);
}

SeriesInfo TelemetryModel::infoOf(const char* name) {
  static const struct {
    const char* name;
    const char* label;
    const char* unit;
  } kInfo[] = {
      {series::kLatencyStages[0], "capture → encoded", "ms"},
      {series::kLatencyStages[1], "capture → sent", "ms"},
      {series::kLatencyStages[2], "capture → received", "ms"},
      {series::kLatencyStages[3], "capture → decoded", "ms"},
      {series::kLatencyStages[4], "capture → uploaded", "ms"},
      {series::kLatencyStages[5], "capture → displayed", "ms"},
      {series::kHeadLatency, "head pose → robot", "ms"},
      {series::kVOp, "v_op (operator head)", "cm/s"},
      {series::kVRob, "v_rob (robot head)", "cm/s"},
      {series::kDeltaS, "Δs (left eye ↔ left camera)", "cm"},
      {series::kXrFrameMs, "render time, both eyes", "ms"},
      {series::kXrMissed, "missed display frames", "frames"},
  };
  for (const auto& i : kInfo)
    if (std::strcmp(i.name, name) == 0) return {i.name, i.label, i.unit};
  if (auto link = MediaLinkSeries::infoOf(name)) return *link;
  if (auto depth = DepthProxySeries::infoOf(name)) return *depth;
  return {name, name, ""};
}

void TelemetryModel::add(TimeSeries* series, double t, double v) {
  series->append(t, v);
  ++counts_.samples;
}

void TelemetryModel::robotRestarted() {
  last_robot_batch_ = 0;
  last_measured_.reset();
}

void TelemetryModel::ingest(const link::proto::Envelope& envelope,
                            std::optional<std::int64_t> robot_to_console_offset_ns) {
  if (!envelope.has_robot_telemetry() && !envelope.has_xr_telemetry()) return;
  if (!robot_to_console_offset_ns) {
    ++counts_.unsynced_batches;
    return;
  }
  if (envelope.has_robot_telemetry())
    ingestRobot(envelope.robot_telemetry(), *robot_to_console_offset_ns);
  else
    ingestXr(envelope.xr_telemetry(), *robot_to_console_offset_ns);
  store_.markChanged();
}

void TelemetryModel::ingestRobot(const link::proto::RobotTelemetry& t, std::int64_t offset) {
  ++counts_.robot_batches;
  if (t.batch() <= last_robot_batch_) last_robot_batch_ = 0;  // numbering restarted
  if (last_robot_batch_ != 0 && t.batch() > last_robot_batch_ + 1)
    counts_.robot_batches_lost += t.batch() - last_robot_batch_ - 1;
  last_robot_batch_ = t.batch();

  for (const auto& f : t.frames()) {
    const double at = robotPlotTime(f.capture_ns(), offset);
    add(stages_[0], at, double(f.encoded_ns() - f.capture_ns()) * 1e-6);
    add(stages_[1], at, double(f.sent_ns() - f.capture_ns()) * 1e-6);
    if (f.has_media()) counts_.samples += link_.addSentFrame(f.media(), robotPlotTime(f.sent_ns(), offset));
  }
  for (const auto& tick : t.ticks()) {
    if (tick.target_new() && tick.target_t_ns() > 0)
      add(head_latency_, robotPlotTime(tick.target_t_ns(), offset),
          double(tick.target_arrival_ns() - tick.target_t_ns()) * 1e-6);
    if (tick.has_t_robot_head_measured() && tick.joint_state_ns() > 0) {
      const Eigen::Vector3d p = positionOf(tick.t_robot_head_measured());
      if (last_measured_ && tick.joint_state_ns() > last_measured_->first) {
        const std::int64_t dt = tick.joint_state_ns() - last_measured_->first;
        if (dt <= kMaxSpeedGapNs)
          add(v_rob_, robotPlotTime(tick.joint_state_ns(), offset),
              (p - last_measured_->second).norm() / (double(dt) * 1e-9) * 100.0);
      }
      if (!last_measured_ || tick.joint_state_ns() > last_measured_->first)
        last_measured_ = {tick.joint_state_ns(), p};
    }
  }
}

void TelemetryModel::ingestXr(const link::proto::XrTelemetry& t, std::int64_t offset) {
  ++counts_.xr_batches;
  if (t.batch() <= last_xr_batch_) {  // the XR app restarted
    last_xr_batch_ = 0;
    last_op_.reset();
    link_.receiverRestarted();
  }
  if (last_xr_batch_ != 0 && t.batch() > last_xr_batch_ + 1)
    counts_.xr_batches_lost += t.batch() - last_xr_batch_ - 1;
  last_xr_batch_ = t.batch();
  xr_mode_ = t.visual_mode();
  xr_radius_ = t.sphere_radius();
  xr_calibration_ = t.calibration_generation();
  if (t.has_depth()) xr_depth_proxy_ = t.depth().proxy();
  if (!t.clock_synced()) {  // the XR app had no offset to the robot: its stamps cannot be mapped
    ++counts_.unsynced_batches;
    return;
  }
  // t_console = t_xr − robot_to_xr + robot_to_console.
  const std::int64_t xr_to_console = offset - t.robot_to_xr_offset_ns();
  const auto xrTime = [&](std::int64_t xr_ns) { return plotTime(xr_ns + xr_to_console); };
  if (t.has_media()) counts_.samples += link_.addReceiveCounts(t.media(), xrTime(t.media().t_ns()));
  if (t.has_depth()) counts_.samples += depth_.add(t.depth(), xrTime(t.depth().t_ns()));
  for (const auto& f : t.frames()) {
    const double at = xrTime(f.display_ns());
    xr_unmeasured_ = UnmeasuredPose{f.pose_unmeasured(), f.holding_measured()};
    if (f.pose_unmeasured()) ++counts_.xr_frames_unmeasured;
    add(frame_ms_, at, f.render_ms());
    add(missed_, at, double(f.missed()));
    if (f.eye_camera_distance_m() >= 0.0) add(delta_s_, at, f.eye_camera_distance_m() * 100.0);
    if (f.head_valid()) {
      const Eigen::Isometry3d T_vr_hmd = link::fromLinkPose(f.t_vr_hmd());
      if (T_vr_hmd.matrix().allFinite()) {
        const Eigen::Vector3d p = T_vr_hmd.translation();
        if (last_op_ && f.display_ns() > last_op_->first && f.display_ns() - last_op_->first <= kMaxSpeedGapNs)
          add(v_op_, at, (p - last_op_->second).norm() / (double(f.display_ns() - last_op_->first) * 1e-9) * 100.0);
        if (!last_op_ || f.display_ns() > last_op_->first) last_op_ = {f.display_ns(), p};
        head_poses_.push_back({at, T_vr_hmd});
      }
    }
    if (f.new_image()) {
      const auto& s = f.stamps();
      // capture is in the robot clock; the XR app's stamps map into it by its offset.
      const double at_capture = robotPlotTime(s.capture_ns(), offset);
      const auto sinceCapture = [&](std::int64_t xr_ns) {
        return double(xr_ns - t.robot_to_xr_offset_ns() - s.capture_ns()) * 1e-6;
      };
      add(stages_[2], at_capture, sinceCapture(s.received_ns()));
      add(stages_[3], at_capture, sinceCapture(s.decoded_ns()));
      add(stages_[4], at_capture, sinceCapture(s.uploaded_ns()));
      add(stages_[5], at_capture, sinceCapture(s.displayed_ns()));
    }
  }
  while (!head_poses_.empty() && head_poses_.front().t < head_poses_.back().t - kHeadPoseHistoryS)
    head_poses_.pop_front();
}

}  // namespace telesphere::console::telemetry
