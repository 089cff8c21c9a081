// SPDX-License-Identifier: MIT
/// @brief The operator's view of a recorded session (issue #18), an OperatorScene fed from the
///        recording instead of the link: the frames and robot states logged up to the display
///        frame's start are handed in (takeFrame, takeState); beginFrame decodes the newest frame
///        on the render thread (both JPEGs, synchronously) and uploads it; the recorded mode,
///        sphere radius and nominal mapping are followed as the live view follows the robot's
///        (xr/frame_loop/robot_view_state.h, the stand-in before a nominal pose included); the
///        study's trial indicator is drawn. Nothing depends on wall time or on threads, so the same
///        inputs give the same pixels.
///
///        Calibration: each frame is rendered with the calibration the robot stamped it with
///        (StereoFrame.calibration_generation), as the recording attached it (takeCalibration),
///        so a calibration applied live mid-session is replayed as it was shown; with
///        follow_recorded_calibrations off (a --calib given to override it) the one given
///        is used throughout.
///
///        H.264/HEVC frames (#34) are decoded as they are taken, every one in order (a predicted
///        frame needs the one before it); the newest decoded pair is shown. A gap in the sequence
///        (a recording begun part way, frames the robot never logged) waits for the next key frame.
///
///        Scene proxy (#35): the one the operator's eyes had, as the XR app's telemetry recorded
///        it (else the session's choice in the robot state); its stereo depth is measured again
///        from the recorded pairs by the same sweep and filter, on the render thread, each pair
///        once when it is first shown, so every run gives the same grids and radii.
///
///        Not replayed: the live view's holding of the last measured frame while unmeasured ones
///        arrive (frames without measured camera poses are shown dimmed at once); the live depth's
///        age (live, the eyes use the newest estimate while the shown pair's own is swept, 13–20 ms;
///        the replay uses the shown pair's own) and the pairs the live worker skipped (the replay
///        sweeps every pair it shows, so its filter has more samples).
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "calib/system_calibration.h"
#include "robot/record/recording_reader.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/frame_loop/operator_view.h"
#include "xr/frame_loop/stereo_view_renderer.h"
#include "xr/video/latency_record.h"
#include "xr/video/video_stream_decoder.h"
#include "xr/video/jpeg_decoder.h"

namespace telesphere::xr::replay {

class RecordedView final : public frame_loop::OperatorScene {
 public:
  /// `render` holds until a recorded state says otherwise (follow_recorded_settings).
  /// `depth_proxy` too, until the recording says otherwise; `depth` configures its stereo depth.
  RecordedView(const calib::SystemCalibration& calibration, const render::RenderSettings& render, bool follow_recorded_settings,
               bool follow_recorded_calibrations = false, std::uint64_t calibration_generation = 0,
               link::DepthProxy depth_proxy = link::DepthProxy::kFixed, const frame_loop::DepthWorkerOptions& depth = {});

  /// A calibration the recording attached (kept by generation for the frames stamped with it).
  /// False with the reason when its text is not a two-camera calibration.
  bool takeCalibration(const record::RecordedCalibration& calibration, std::string* error);

  /// The newest frame logged so far (replaces one not yet shown) / the newest robot state.
  void takeFrame(record::RecordedFrame&& frame);
  void takeState(const link::proto::RobotState& state) { state_ = state; }
  /// The XR app's telemetry batch as recorded: the scene proxy its eyes had.
  void takeXrTelemetry(const link::proto::XrTelemetry& telemetry);
  /// The link's cues a live view showed (views.csv): the image's saturation and the overlay,
  /// drawn again over the next frames' eyes so the replay gives the live run's pixels.
  void setLinkCues(const frame_loop::LinkState& state, float image_saturation);

  bool beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display_ns, bool valid, std::string* error) override;
  bool renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view, GLuint framebuffer,
                 std::string* error) override;
  void endFrame(std::int64_t shown_ns, double render_ms, std::uint64_t missed_frames) override;
  std::optional<Eigen::Isometry3d> T_cam_eye(int eye, const Eigen::Isometry3d& T_vr_eye) const override {
    return renderer_.cameraFromEye(eye, T_robot_vr_, T_vr_eye);
  }

  /// The frame on the GPU (nothing before the first).
  const std::shared_ptr<const video::DecodedStereoFrame>& frame() const { return renderer_.frame(); }
  /// The live view's figures where they apply (times on the robot's clock: the recording's).
  frame_loop::OperatorViewStats stats() const;
  /// Frames whose JPEGs (or H.264/HEVC access units) did not decode (the previous frame stayed on show).
  std::uint64_t undecodable() const { return undecodable_; }
  /// H.264/HEVC frames passed over until a key frame after a gap in the recording.
  std::uint64_t awaitingKeyFrame() const { return awaiting_key_frame_; }
  /// Frames replaced by a newer one before a display frame began (logged within one display period).
  std::uint64_t replacedUnshown() const { return replaced_unshown_; }

 private:
  frame_loop::StereoViewRenderer renderer_;
  bool follow_settings_;
  bool follow_calibrations_;
  std::map<std::uint64_t, calib::SystemCalibration> calibrations_;  ///< by generation
  /// H.264/HEVC: both frames decoded in order as they are taken; nothing when one did not.
  std::shared_ptr<const video::DecodedStereoFrame> decodeVideoPair(record::RecordedFrame& frame, link::VideoCodec codec);
  /// The decoded pair on the GPU, with its calibration, gain and counts.
  bool show(const std::shared_ptr<const video::DecodedStereoFrame>& decoded, std::string* error);
  /// The recorded state's nominal mapping and settings, the newest frame taken decoded and shown.
  bool takePending(std::string* error);
  /// The recorded scene proxy followed; the pair on show swept (once) when it needs depth.
  void followDepthProxy();

  link::DepthProxy depth_proxy_;
  frame_loop::DepthWorkerOptions depth_options_;
  std::unique_ptr<frame_loop::DepthWorker> depth_;  ///< on this thread; null until a proxy needs depth
  std::optional<link::DepthProxy> xr_depth_proxy_;  ///< from the newest recorded XR batch that says

  video::JpegDecoder decoder_;
  std::unique_ptr<video::VideoStreamDecoder> video_[2];  ///< H.264/HEVC, per camera (made with the first frame)
  std::optional<record::RecordedFrame> pending_;
  std::shared_ptr<const video::DecodedStereoFrame> pending_decoded_;  ///< H.264/HEVC: decoded at take time
  std::optional<link::proto::RobotState> state_;
  std::optional<frame_loop::LinkState> link_cues_;  ///< views mode: the live run's cues
  Eigen::Isometry3d T_robot_vr_ = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> T_robot_vr_stand_in_;
  bool uploaded_this_frame_ = false;
  std::uint64_t undecodable_ = 0, replaced_unshown_ = 0, awaiting_key_frame_ = 0;
  frame_loop::OperatorViewStats stats_;
  video::LatencyRecord render_ms_, age_ms_, upload_ms_, decode_ms_;  ///< bounded: a recording may be hours long
};

}  // namespace telesphere::xr::replay
