// SPDX-License-Identifier: MIT
/// @brief Telemetry from the link → the console's plotted series, every sample at its source
///        time (DESIGN.md §7). Qt-free.
///
/// One clock: the console's steady clock, shown as seconds since the console started (the plot
/// clock). Robot stamps map by the console's ping offset: t_console = t_robot + robot_to_console;
/// XR stamps first into the robot clock by the offset the XR app measured and sent along with
/// its batch (t_robot = t_xr − robot_to_xr), then the same way. Receive times are never used.
///
/// Series (name: what, unit, plotted at):
///   latency.encoded … latency.displayed  capture → that stage, ms, at the capture time (the
///       robot's sent frames give encoded and sent, the XR app's first display of a frame gives
///       received, decoded, uploaded and displayed: the stacked image-latency plot);
///   head.latency   head pose sampled by the XR app → taken by the robot's head loop, ms, at the
///                  sample time;
///   head.v_op      operator head speed (XR head poses), cm/s, at the pose's display time;
///   head.v_rob     robot head speed (forward kinematics of the measured joints), cm/s, at the
///                  joint state's time (paper Fig. 6 shows both);
///   head.delta_s   Δs, left eye ↔ left camera at capture time, cm, at the display time (Fig. 7);
///   xr.frame_ms    render time of both eyes, ms, at the display time;
///   xr.missed      display periods missed before a frame, at its display time;
///   link.*         the media path (MediaLinkSeries): the robot's per frame sent, at the send
///                  time, and the XR receiver's per batch;
///   depth.*        the operator's scene proxy (DepthProxySeries): each eye's radius, the stereo
///                  depth's confidence, age and cost, per XR batch.
/// All exist (empty) from construction on.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>

#include "console/telemetry/depth_proxy_series.h"
#include "console/telemetry/media_link_series.h"
#include "console/telemetry/series_store.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::telemetry {

/// The series names above, for plots and tests.
namespace series {
inline constexpr const char* kLatencyStages[] = {"latency.encoded", "latency.sent", "latency.received",
                                                 "latency.decoded", "latency.uploaded", "latency.displayed"};
inline constexpr const char* kHeadLatency = "head.latency";
inline constexpr const char* kVOp = "head.v_op";
inline constexpr const char* kVRob = "head.v_rob";
inline constexpr const char* kDeltaS = "head.delta_s";
inline constexpr const char* kXrFrameMs = "xr.frame_ms";
inline constexpr const char* kXrMissed = "xr.missed";
}  // namespace series

/// One operator head pose as the XR app reported it (for the nominal-pose step).
struct HeadPoseSample {
  double t = 0.0;  ///< plot clock, s (the pose's display time)
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
};

struct TelemetryCounts {
  std::uint64_t robot_batches = 0, xr_batches = 0;
  std::uint64_t robot_batches_lost = 0, xr_batches_lost = 0;  ///< gaps in the numbering
  std::uint64_t unsynced_batches = 0;  ///< dropped: a clock offset was not known yet
  std::uint64_t samples = 0;           ///< appended to series
  std::uint64_t xr_frames_unmeasured = 0;  ///< display frames showing a frame without a measured pose
};

class TelemetryModel {
 public:
  /// `origin_console_ns`: the console clock's zero of the plot clock.
  TelemetryModel(SeriesStore& store, std::int64_t origin_console_ns);

  /// Adds the samples of a robot_telemetry or xr_telemetry envelope (others are ignored).
  /// Without robot_to_console_offset_ns (no pong yet) the batch is counted and dropped.
  void ingest(const link::proto::Envelope& envelope,
              std::optional<std::int64_t> robot_to_console_offset_ns);

  /// Console clock (steady ns) → plot clock (s).
  double plotTime(std::int64_t console_ns) const { return double(console_ns - origin_ns_) * 1e-9; }

  /// The robot process changed (new instance): its batch numbering and joint states restart.
  void robotRestarted();

  const TelemetryCounts& counts() const { return counts_; }
  /// Head poses of the last kHeadPoseHistoryS seconds of plot time, oldest first.
  const std::deque<HeadPoseSample>& recentHeadPoses() const { return head_poses_; }
  static constexpr double kHeadPoseHistoryS = 2.0;
  /// What the XR app renders with, from its newest batch.
  std::optional<link::proto::VisualMode> xrVisualMode() const { return xr_mode_; }
  std::optional<double> xrSphereRadius() const { return xr_radius_; }
  /// The scene proxy the XR app renders with (nothing before a batch that says: an older XR app).
  std::optional<link::proto::DepthProxyProto> xrDepthProxy() const { return xr_depth_proxy_; }
  /// The robot calibration generation the XR app renders with (0: its start-up --calib).
  std::optional<std::uint64_t> xrCalibrationGeneration() const { return xr_calibration_; }
  /// Whether the XR app's newest display frame showed a camera frame without a measured camera
  /// pose (dimmed), or held the last measured one back from such frames; empty before any.
  struct UnmeasuredPose {
    bool shown_dimmed = false, holding_measured = false;
  };
  std::optional<UnmeasuredPose> xrUnmeasuredPose() const { return xr_unmeasured_; }

  static SeriesInfo infoOf(const char* name);

 private:
  void ingestRobot(const link::proto::RobotTelemetry& t, std::int64_t robot_to_console_ns);
  void ingestXr(const link::proto::XrTelemetry& t, std::int64_t robot_to_console_ns);
  void add(TimeSeries* series, double t, double v);
  double robotPlotTime(std::int64_t robot_ns, std::int64_t robot_to_console_ns) const {
    return plotTime(robot_ns + robot_to_console_ns);
  }

  SeriesStore& store_;
  std::int64_t origin_ns_;
  // The series, created up front (the store keeps them; only their samples come and go).
  TimeSeries* stages_[6];
  TimeSeries *head_latency_, *v_op_, *v_rob_, *delta_s_, *frame_ms_, *missed_;
  MediaLinkSeries link_;
  DepthProxySeries depth_;
  TelemetryCounts counts_;
  std::uint64_t last_robot_batch_ = 0, last_xr_batch_ = 0;
  std::optional<std::pair<std::int64_t, Eigen::Vector3d>> last_measured_;  ///< robot clock
  std::optional<std::pair<std::int64_t, Eigen::Vector3d>> last_op_;       ///< XR clock
  std::deque<HeadPoseSample> head_poses_;
  std::optional<link::proto::VisualMode> xr_mode_;
  std::optional<double> xr_radius_;
  std::optional<link::proto::DepthProxyProto> xr_depth_proxy_;
  std::optional<std::uint64_t> xr_calibration_;
  std::optional<UnmeasuredPose> xr_unmeasured_;
};

}  // namespace telesphere::console::telemetry
