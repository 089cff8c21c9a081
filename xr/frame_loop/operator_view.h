// SPDX-License-Identifier: MIT
/// @brief The per-frame work of the operator app that does not depend on where the head pose
///        comes from or where the eyes go (DESIGN.md §2–§4), shared by the OpenXR, desktop and
///        offscreen modes: the head pose at the predicted display time goes to the robot as the
///        head target (link clock, latest wins); the newest decoded stereo frame goes to the
///        GPU; the robot's mode, sphere radius and scene proxy are followed live (the console
///        changes them through the robot); the nominal mapping T_robot_vr comes from the robot once the
///        nominal pose is captured (before that, a stand-in that puts the head at the left
///        camera); both eyes are rendered through it. Control requests (capture the nominal
///        pose, change mode or radius) are sent without blocking the frame loop.
///
///        Telemetry for the console (link XrTelemetry, batched every kTelemetryPeriodNs): one
///        sample per display frame with its head pose and display time, render time, missed
///        periods, the camera frame shown (all stage stamps on its first display) and Δs, the
///        distance from the left eye to the left camera at capture time (paper Fig. 7); per batch
///        the scene proxy in use with each eye's radius and the stereo depth's confidence and age.
///
///        Frames whose camera pose was not measured (link pose_source FIXED_CALIBRATION: the
///        robot had no joint state for the capture time, e.g. the arm's report stream is
///        down) would put the scene in the wrong place. Once a measured frame has been shown,
///        such a frame is not taken for up to hold_measured_s: the last measured frame stays
///        (right geometry, growing age); after that, or before any measured frame, unmeasured
///        frames are shown dimmed (image gain kUnmeasuredGain) so the operator sees that the view
///        is not tracked. Counted, logged once per streak, and flagged in the telemetry.
///
///        Calibration (follow_robot_calibration): the robot names the calibration it uses in its
///        state (a generation: the console applies and reverts calibrations live, DESIGN.md §6);
///        a new one is fetched (get_calibration, off the frame loop) and its camera models are
///        taken at the first frame the robot stamped with it (StereoFrame.calibration_generation),
///        so poses and intrinsics of one frame always belong together: a frame stamped with a
///        generation whose models have not arrived yet is not shown (the last frame stays on show,
///        counted in frames_held_for_calibration) until they have. The calibration given at
///        start-up stands for the robot's first generation (1); a robot already past it is
///        shown only once its calibration is fetched.
///
///        Frame protocol, on the thread whose GL context is current:
///          beginFrame(T_vr_hmd, display) → renderEye(0, …) → renderEye(1, …) → endFrame(…).
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "calib/system_calibration.h"
#include "robot/link/control_queue.h"
#include "robot/link/link_client.h"
#include "robot/link/link_endpoints.h"
#include "xr/frame_loop/link_state_overlay.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/render/eye_view.h"
#include "xr/video/latency_record.h"
#include "xr/video/media_frame_source.h"
#include "xr/video/stereo_frame_decoder.h"
#include "xr/frame_loop/stereo_view_renderer.h"

namespace telesphere::xr::frame_loop {

struct OperatorViewOptions {
  link::LinkEndpoints endpoints;
  /// "INSECURE LINK" in red in the view while the link has no keys (the app's --insecure).
  bool warn_insecure_link = false;
  /// Until the robot's state says otherwise: mode and radius are then the robot's.
  render::RenderSettings render;
  /// Follow the mode and radius the robot publishes (off: the command line's stay).
  bool follow_robot_settings = true;
  /// How long the last measured frame is held while only unmeasured ones arrive, s.
  double hold_measured_s = 1.0;
  /// Render with the robot's calibration (RobotState.calibration_generation, fetched with
  /// get_calibration) instead of the one given at start-up (off: the start-up one stays).
  bool follow_robot_calibration = true;
  /// Images the upload ring holds (0: no ring; every image is uploaded from the decoder's memory
  /// inside the frame).
  int upload_ring_slots = StereoViewRenderer::kDefaultUploadSlots;
  /// Frames over the robot's UDP media path (port + 4; DESIGN.md §9) instead of the ZeroMQ link.
  bool media_link = false;
  int media_port = 0;  ///< its UDP port when not endpoints.base_port + 4 (a relay in between)
  /// Ask the robot again for chunks of the newest frame that parity cannot rebuild (FrameAssembler).
  bool media_repair = true;
  /// With the media path: head targets also on the ZeroMQ uplink (both ways; the robot keeps the
  /// newest by stamp). Off: on the media path only (to measure it alone).
  bool head_targets_on_zmq = true;
  /// When the picture is too old, the stream below nominal, the robot behind (link_state_overlay.h).
  LinkStateOptions link_state;
  /// The scene proxy (#35): fixed (the sphere of render.radius, as the robot sets it), or one
  /// radius or the grid from the stereo pair's depth (a DepthWorker beside the loop).
  link::DepthProxy depth_proxy = link::DepthProxy::kFixed;
  DepthWorkerOptions depth;
  /// With one radius or the grid: a new camera image waits up to this long (ms) for the depth
  /// swept from its own pair before it is shown; the one on show stays meanwhile. 0 (default): shown
  /// at once with the newest depth the worker has, which is the pair before's (no added latency; an
  /// object moving in depth is placed one sweep late). Measured both ways: xr/README.md.
  double depth_hold_ms = 0.0;
};

/// Whole-run figures of the operator loop (the loop adds its own pacing figures).
struct OperatorViewStats {
  std::uint64_t frames = 0;               ///< endFrame calls
  std::uint64_t frames_with_image = 0;    ///< of those, frames that showed a camera image
  std::uint64_t stereo_frames_shown = 0;  ///< distinct camera frames displayed
  std::uint64_t head_targets_sent = 0;
  std::uint64_t settings_changes = 0;     ///< mode/radius changes taken from the robot
  double render_ms_p50 = 0, render_ms_p99 = 0;
  double image_age_p50_ms = 0, image_age_p99_ms = 0;  ///< capture → display
  /// The render thread's time for a new camera frame: the copy commands from the upload ring (or,
  /// from the decoder's own memory, the whole upload), ms.
  double upload_ms_render_thread_p50 = 0, upload_ms_render_thread_p99 = 0;
  double decode_ms_p50 = 0;                ///< one JPEG's decode on a decoder thread
  std::uint64_t images_in_upload_slots = 0;  ///< camera images decoded straight into GL buffer memory
  std::uint64_t images_in_own_memory = 0;    ///< … into the decoder's memory (uploaded from there)
  double pose_to_display_ms_p50 = 0;  ///< head-pose sample (frame start) → predicted display
  bool nominal_from_robot = false;        ///< T_robot_vr came from the robot (else the stand-in)
  std::uint64_t unmeasured_frames_shown = 0;  ///< distinct frames shown dimmed (pose not measured)
  std::uint64_t unmeasured_frames_held_back = 0;  ///< passed over while a measured one was held
  /// Frames not shown because their calibration's models had not arrived (the last one stayed).
  std::uint64_t frames_held_for_calibration = 0;
  std::uint64_t calibration_generation = 0;  ///< the robot's calibration rendered with (0: start-up one)
  /// The video link: "zmq" (the ZeroMQ link) or "udp" (the media path), and what the latter lost.
  std::string video_link = "zmq";
  std::uint64_t media_datagrams = 0, media_frames_whole = 0, media_frames_concealed = 0, media_frames_lost = 0;
  std::uint64_t media_bands_lost = 0;
  std::uint64_t media_chunks_fec = 0;        ///< rebuilt from parity
  std::uint64_t media_chunks_requested = 0, media_chunks_repaired = 0;  ///< asked for again, arrived in time
  std::uint64_t media_frames_superseded = 0;  ///< incomplete when a newer one was delivered
  std::uint64_t frames_concealed = 0, rows_concealed = 0, rows_grey = 0;  ///< painted from the previous frame
  std::string video_codec = "mjpeg";      ///< what the frames carry (#34)
  std::uint64_t key_frames_requested = 0;  ///< H.264/HEVC: key frames asked of the robot after a loss
  std::uint64_t frames_awaiting_key_frame = 0;  ///< H.264/HEVC: frames refused until that key frame
  /// Display frames with the link's cues (link_state_overlay.h): border tinted (image older than
  /// 250 ms), stale (older than 1 s: grey), the stream below nominal, the robot behind.
  std::uint64_t frames_tinted = 0, frames_stale = 0, frames_stream_below_nominal = 0, frames_robot_behind = 0;
  std::uint64_t calibration_changes = 0;     ///< calibrations taken from the robot
  /// The scene proxy and its depth (#35): estimates published by the depth worker, the last
  /// one's CPU ms (both cameras), the left camera's radius and matched tiles in it.
  std::string depth_proxy = "fixed";
  std::uint64_t depth_estimates = 0, depth_pairs_skipped = 0;
  double depth_sweep_ms = 0, depth_radius_left_m = 0, depth_matched_fraction = 0;
  /// The last estimate's left sweep: earlier images from the arm's motion it took, the longest
  /// baseline among them (m) and the tiles they decided (DepthWorkerOptions::motion_views).
  int depth_motion_views_left = 0, depth_tiles_decided_by_motion_left = 0;
  double depth_motion_baseline_left_m = 0;
  /// The last estimate's pair costs came from the GPU (DepthWorkerOptions::gpu); where the GPU was
  /// asked for and is not used, why.
  bool depth_sweep_on_gpu = false;
  std::string depth_gpu_unavailable;
  /// With depth_hold_ms: images shown with their own pair's depth after waiting for it, images
  /// shown without it when the wait ran out, and the display frames an image waited (p50, p99 ms).
  std::uint64_t depth_images_held = 0, depth_hold_timeouts = 0;
  double depth_hold_ms_p50 = 0, depth_hold_ms_p99 = 0;
  /// Images whose first display frame had the depth swept from their own pair (any hold setting;
  /// without the hold the depth on show is the pair before's, so this stays near 0).
  std::uint64_t depth_images_with_own_depth = 0;
};

/// `out`'s depth_* figures: the proxy's name and, with a worker, its counts, last sweep and the
/// newest estimate's left radius and matched tiles (the live view and the replay).
void addDepthFigures(link::DepthProxy proxy, const DepthWorker* worker, OperatorViewStats* out);

class OperatorView final : public OperatorScene {
 public:
  OperatorView(const calib::SystemCalibration& calibration, const OperatorViewOptions& options);
  ~OperatorView();
  OperatorView(const OperatorView&) = delete;
  OperatorView& operator=(const OperatorView&) = delete;

  /// Start of a display frame. `T_vr_hmd` is the head pose predicted for `display_ns` (link
  /// clock, steady ns); `valid` false sends an invalid target (the robot holds). Uploads the
  /// newest stereo frame, takes mode/radius/nominal from the robot's state. False with the
  /// reason when the upload fails (a frame that does not fit the calibration).
  bool beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display_ns, bool valid,
                  std::string* error) override;
  /// Renders eye `eye` (0 left, 1 right) whose pose in the VR frame is `T_vr_eye` into
  /// `framebuffer` (fov and size from `view`). Border colour before the first frame.
  bool renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view,
                 GLuint framebuffer, std::string* error) override;
  /// The projection map of eye `eye` for the same pose (StereoViewRenderer::renderProjectionMap).
  bool renderProjectionMap(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view,
                           GLuint framebuffer, std::string* error) {
    return renderer_.renderProjectionMap(eye, T_robot_vr_, T_vr_eye, view, framebuffer, error);
  }
  /// End of the frame: `shown_ns` is when it is displayed (link clock), `render_ms` the work
  /// of both eyes. Sends XrStats to the robot once a second.
  void endFrame(std::int64_t shown_ns, double render_ms, std::uint64_t missed_frames) override;

  /// How often a telemetry batch goes to the robot (for the console).
  static constexpr std::int64_t kTelemetryPeriodNs = 100'000'000;

  /// Asks the robot to capture the nominal pose from the latest head target / to change the
  /// mode / the sphere radius. Never blocks: the reply is logged, and the new values reach
  /// this view through the robot's state.
  void requestCaptureNominal();
  void requestMode(link::VisualMode mode);
  void requestRadius(double radius_m);
  /// The operator's keys: the next mode of the cycle; the radius times `factor`, kept in the
  /// link's accepted range (robot/link/sphere_radius.h).
  void requestNextMode() { requestMode(link::nextVisualMode(settings().mode)); }
  /// The scene proxy, live (#35): a depth worker starts with the first proxy that needs depth and
  /// stays. setDepthProxy changes it here at once. The session's choice is the robot's (its state,
  /// followed like the mode, once somebody chose one: the console, the operator's key, the robot's
  /// --depth-proxy); requestDepthProxy asks the robot for it when one is heard (so the console and
  /// the recording see it), else changes it here. The operator's key cycles fixed → radius → grid.
  void setDepthProxy(link::DepthProxy proxy);
  void requestDepthProxy(link::DepthProxy proxy);
  void cycleDepthProxy() { requestDepthProxy(link::nextDepthProxy(options_.depth_proxy)); }
  link::DepthProxy depthProxy() const { return options_.depth_proxy; }
  void requestRadiusScaled(double factor);

  /// The newest decoded frame is on the GPU (anything to show).
  bool hasImage() const { return renderer_.frame() != nullptr; }
  /// On a keyed link's media path (DESIGN.md §10): asks the robot for a session key when there is
  /// none, the robot restarted, or its frames stopped for 3 s (at most every 2 s, never blocking).
  /// beginFrame calls it; a caller that waits for the first frame before its loop calls it too.
  void keepMediaSession();
  /// Seconds since the last new camera frame went up (since construction before the first), as
  /// of the last beginFrame. The view keeps showing the last frame while the robot is silent;
  /// a warning is logged when this passes kSilentRobotS, and a note when frames come back.
  double secondsWithoutNewFrame() const { return double(frame_begin_ns_ - last_new_frame_ns_) * 1e-9; }
  static constexpr double kSilentRobotS = 2.0;
  /// Image gain of frames whose camera pose was not measured.
  static constexpr float kUnmeasuredGain = 0.4f;
  /// Whether the frame on show has no measured camera pose (it is dimmed).
  bool showingUnmeasured() const { return showing_unmeasured_; }
  const std::shared_ptr<const video::DecodedStereoFrame>& frame() const { return renderer_.frame(); }
  const render::RenderSettings& settings() const { return renderer_.settings(); }
  const Eigen::Isometry3d& T_robot_vr() const { return T_robot_vr_; }
  /// The pose an eye at T_vr_eye is rendered with in the frame on the GPU (T_cam_eye); nothing
  /// before the first frame.
  std::optional<Eigen::Isometry3d> T_cam_eye(int eye, const Eigen::Isometry3d& T_vr_eye) const override {
    return renderer_.cameraFromEye(eye, T_robot_vr_, T_vr_eye);
  }
  /// The last control reply's text ("capture_nominal: ok", "set_mode: refused: …"), for a UI.
  std::string lastControlResult() const;
  /// A calibration fetched from the robot waits for the first frame stamped with it.
  bool calibrationPending() const;

  /// The link's cues of the frame in progress (what drawLinkState drew over each eye).
  const LinkState& linkState() const { return link_state_; }
  link::LinkClient& client() { return client_; }
  video::StereoFrameDecoder& decoder() { return decoder_; }
  /// The media path's receiver (null on the ZeroMQ link).
  const video::MediaFrameSource* media() const { return media_.get(); }
  OperatorViewStats stats() const;

 private:
  void sendControl(link::proto::ControlRequest request, std::string what);
  /// setDepthProxy without its log line (the caller says why).
  void switchDepthProxy(link::DepthProxy proxy);
  /// The scene proxy in use and the depth behind it, for a telemetry batch at `now_ns` (link clock).
  void fillDepthState(std::int64_t now_ns, link::proto::DepthProxyState* out) const;
  /// The frame to show now: the decoder's newest, unless the rule above holds the current one.
  std::shared_ptr<const video::DecodedStereoFrame> frameToShow();
  /// With depth_hold_ms: `next` once the depth worker has its own estimate or the wait has run
  /// out, else `current` (next is offered to the worker meanwhile).
  std::shared_ptr<const video::DecodedStereoFrame> holdForOwnDepth(std::shared_ptr<const video::DecodedStereoFrame> next,
                                                                  std::shared_ptr<const video::DecodedStereoFrame> current);
  /// Asks for the robot's calibration when its state names one this view does not render with.
  void followRobotCalibration(const link::proto::RobotState& state);
  /// Takes the fetched calibration once `frame` is stamped with it (or there is no frame).
  bool takeFetchedCalibration(const video::DecodedStereoFrame* frame, std::string* error);

  link::LinkClient client_;
  StereoViewRenderer renderer_;  ///< before the decoder: its upload ring outlives the decoder's frames
  std::unique_ptr<video::MediaFrameSource> media_;  ///< before the decoder, which takes frames from it
  video::StereoFrameDecoder decoder_;
  std::unique_ptr<DepthWorker> depth_;  ///< null with the fixed proxy
  OperatorViewOptions options_;
  Eigen::Isometry3d T_robot_vr_ = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> T_robot_vr_stand_in_;
  std::int64_t uploaded_this_frame_ns_ = -1;  ///< upload time when this frame uploaded a new image
  std::int64_t frame_begin_ns_ = 0;
  std::int64_t last_new_frame_ns_ = 0;  ///< set at construction, then at every new frame
  bool robot_silent_ = false;           ///< the silence warning was given
  link::proto::TrialIndicator trial_;  ///< the study's trial, from the robot's state
  bool showing_unmeasured_ = false;     ///< the frame on show has no measured pose
  bool holding_measured_ = false;       ///< a newer unmeasured frame is passed over
  std::int64_t unmeasured_since_ns_ = -1;  ///< first unmeasured frame of the streak (-1: none)
  std::uint64_t last_unmeasured_sequence_ = 0;
  std::uint64_t last_held_for_calibration_ = 0;  ///< the last frame held back for its calibration
  std::int64_t depth_hold_since_ns_ = -1;  ///< when a newer image began to wait for its depth (-1: none waits)
  video::LatencyRecord depth_hold_ms_;     ///< per image shown after waiting, how long it waited
  static constexpr std::int64_t kCalibrationRetryNs = 3'000'000'000;
  std::atomic<std::int64_t> calibration_retry_ns_{kCalibrationRetryNs};  ///< doubles after each refusal
  OperatorViewStats stats_;
  // The session's figures in bounded memory (hours at 90 Hz), and the last second's for the console.
  video::LatencyRecord render_ms_, age_ms_, upload_ms_, pose_lead_ms_;
  std::vector<double> render_ms_last_second_, age_ms_last_second_;
  std::int64_t last_stats_ns_ = 0;
  std::uint64_t frames_at_last_stats_ = 0;
  link::proto::XrFrame telemetry_frame_;  ///< the sample of the frame in progress
  LinkState link_state_;                  ///< the cues of the frame in progress
  link::proto::XrTelemetry telemetry_;    ///< the batch in progress
  std::int64_t last_telemetry_ns_ = 0;
  std::uint64_t missed_at_last_frame_ = 0;

  mutable std::mutex control_result_mutex_;
  std::string last_control_result_;
  std::uint64_t calibration_requested_ = 0;  ///< generation asked for (0: none in flight)
  std::int64_t calibration_requested_ns_ = 0;
  /// A keyed link's media session (keepMediaSession): the robot instance whose key the receiver
  /// holds, when it was last asked for, whether a request is out.
  std::atomic<std::uint64_t> media_session_instance_{0};
  std::int64_t media_session_requested_ns_ = 0;
  std::atomic<bool> media_session_in_flight_{false};
  struct FetchedCalibration {
    std::uint64_t generation = 0;
    calib::SystemCalibration calibration;
    std::string source;
  };
  std::optional<FetchedCalibration> fetched_calibration_;  ///< under control_result_mutex_
  link::ControlQueue control_;  ///< after what its replies write to: it stops first
};

}  // namespace telesphere::xr::frame_loop
