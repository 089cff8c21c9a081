// SPDX-License-Identifier: MIT
/// @brief OperatorView: head target out, newest frame up, robot settings followed, eyes rendered.
#include "xr/frame_loop/operator_view.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "calib/calibration_file.h"
#include "robot/link/link_pose.h"
#include "robot/link/proto_enums.h"
#include "robot/link/sphere_radius.h"
#include "xr/frame_loop/robot_view_state.h"
#include "xr/video/latency_figure.h"
#include "xr/frame_loop/trial_indicator.h"

namespace telesphere::xr::frame_loop {
namespace {

video::StereoFrameDecoder::Options decoderOptions(const StereoViewRenderer& renderer, video::MediaFrameSource* media) {
  video::StereoFrameDecoder::Options options;
  options.upload_slots = renderer.uploadSlots();
  if (media) options.frame_source = [media](std::chrono::milliseconds timeout) { return media->waitFrame(timeout); };
  return options;
}

/// The media path's receiver when asked for; throws std::runtime_error when it cannot open.
std::unique_ptr<video::MediaFrameSource> openMedia(const OperatorViewOptions& options) {
  if (!options.media_link) return nullptr;
  std::string error;
  const int port = options.media_port > 0 ? options.media_port : options.endpoints.base_port + link::LinkEndpoints::kMedia;
  auto media = video::MediaFrameSource::open(options.endpoints.host, port, options.media_repair,
                                             options.endpoints.credentials.secure(), &error);
  if (!media) throw std::runtime_error(error);
  return media;
}

}  // namespace

OperatorView::OperatorView(const calib::SystemCalibration& calibration,
                           const OperatorViewOptions& options)
    // On the media path frames come by UDP only: a ZeroMQ copy would share the operator's downlink.
    : client_(options.endpoints, link::LinkClient::Options{.frames = !options.media_link}),
      renderer_(calibration, options.render, options.upload_ring_slots),
      media_(openMedia(options)),
      decoder_(client_, decoderOptions(renderer_, media_.get())),
      options_(options),
      frame_begin_ns_(link::linkNowNs()),
      last_new_frame_ns_(frame_begin_ns_),
      control_(client_) {
  if (options.depth_proxy != link::DepthProxy::kFixed) depth_ = std::make_unique<DepthWorker>(calibration, options.depth);
}

OperatorView::~OperatorView() = default;

bool OperatorView::beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display_ns,
                              bool valid, std::string* error) {
  frame_begin_ns_ = link::linkNowNs();
  link::proto::HeadTarget target;
  target.set_t_ns(frame_begin_ns_);
  target.set_predicted_display_ns(display_ns);
  link::toLinkPose(valid ? T_vr_hmd : Eigen::Isometry3d::Identity(), target.mutable_t_vr_hmd());
  target.set_valid(valid);
  const auto clock = client_.clock().estimate();
  if (clock) target.set_t_robot_ns(frame_begin_ns_ - clock->server_to_client_offset_ns);
  if (options_.head_targets_on_zmq || !media_) client_.sendHeadTarget(target);
  if (media_) {
    // The same target, stamped as the ZeroMQ copy is, on the media path: what arrives first counts.
    target.set_sender_instance(client_.instance());
    media_->sendHeadTarget(target);
    if (clock) media_->setRoundTripHintNs(clock->round_trip_ns);
  }
  telemetry_frame_.Clear();
  telemetry_frame_.set_display_ns(display_ns);
  telemetry_frame_.set_head_valid(valid);
  if (valid) link::toLinkPose(T_vr_hmd, telemetry_frame_.mutable_t_vr_hmd());
  telemetry_frame_.set_eye_camera_distance_m(-1.0);
  ++stats_.head_targets_sent;
  if (valid) pose_lead_ms_.add(double(display_ns - frame_begin_ns_) * 1e-6);

  // The robot's state: nominal mapping, and (when followed) mode and radius.
  const auto state = client_.latestRobotState();
  if (state && state->nominal_set()) {
    T_robot_vr_ = link::fromLinkPose(state->t_robot_vr());
    stats_.nominal_from_robot = true;
  } else if (T_robot_vr_stand_in_) {
    T_robot_vr_ = *T_robot_vr_stand_in_;
  }
  trial_ = state ? state->trial() : link::proto::TrialIndicator();
  if (state && options_.follow_robot_calibration) followRobotCalibration(*state);
  keepMediaSession();
  if (state && options_.follow_robot_settings) {
    const render::RenderSettings settings = withRobotSettings(renderer_.settings(), *state);
    if (settings.mode != renderer_.settings().mode || settings.radius != renderer_.settings().radius) {
      spdlog::info("operator view: mode {} radius {} m (from the robot; was {} {} m)",
                   link::visualModeName(settings.mode), settings.radius,
                   link::visualModeName(renderer_.settings().mode), renderer_.settings().radius);
      renderer_.setSettings(settings);
      ++stats_.settings_changes;
    }
    const auto proxy = link::fromProto(state->depth_proxy());  // nothing: nobody chose (the view's own)
    if (proxy && *proxy != options_.depth_proxy) {
      spdlog::info("operator view: scene proxy {} from the robot (was {})", link::depthProxyName(*proxy),
                   link::depthProxyName(options_.depth_proxy));
      switchDepthProxy(*proxy);
    }
  }

  const auto before = renderer_.frame();
  auto show = frameToShow();
  if (!takeFetchedCalibration(show.get(), error)) return false;
  if (options_.follow_robot_calibration && show && show != before) {
    // Poses of a calibration whose camera models have not arrived: never drawn with the old
    // models; the last frame stays until they come.
    const std::uint64_t g = show->frame.calibration_generation(), m = stats_.calibration_generation;
    if (g != 0 && g != m && !(m == 0 && g == 1)) {
      if (show->frame.sequence() != last_held_for_calibration_) ++stats_.frames_held_for_calibration;
      last_held_for_calibration_ = show->frame.sequence();
      show = before;
    }
  }
  const bool hold_for_depth = depth_ && options_.depth_hold_ms > 0.0 && options_.depth_proxy != link::DepthProxy::kFixed;
  if (hold_for_depth && show && show != before) show = holdForOwnDepth(show, before);
  if (!renderer_.setFrame(show, error)) return false;
  uploaded_this_frame_ns_ = renderer_.frame() != before ? renderer_.uploadedNs() : -1;
  if (depth_) {
    // The pair on show goes to the depth worker (a pointer swap; with the hold it went there while
    // it waited, and offering the one on show again would put an older pair back); the eyes take
    // the newest estimate it has, never waiting for one.
    if (!hold_for_depth) depth_->offer(renderer_.frame());
    const auto estimate = depth_->newest();
    renderer_.setDepth(options_.depth_proxy, estimate);
    const auto& frame = renderer_.frame();
    if (frame && frame != before && estimate && estimate->frame_sequence == frame->frame.sequence())
      ++stats_.depth_images_with_own_depth;
  }
  // The link's cues for this display: the image's age when it is shown, the stream's settings.
  link_state_ = LinkState{};
  link_state_.insecure = options_.warn_insecure_link && !options_.endpoints.credentials.secure();
  if (const auto& frame = renderer_.frame()) {
    const std::int64_t capture_robot = frame->frame.stamps().capture_ns();
    const std::int64_t capture = client_.clock().serverToClient(capture_robot).value_or(capture_robot);
    link_state_.image_age_ms = double(display_ns - capture) * 1e-6;
    link_state_.stream_text = streamText(frame->frame.stream());
  }
  const float saturation = imageSaturationFor(link_state_.image_age_ms, options_.link_state);
  if (renderer_.settings().image_saturation != saturation) {
    render::RenderSettings settings = renderer_.settings();
    settings.image_saturation = saturation;
    renderer_.setSettings(settings);
  }
  if (uploaded_this_frame_ns_ >= 0) {
    last_new_frame_ns_ = frame_begin_ns_;
    if (robot_silent_) spdlog::info("operator view: camera frames from the robot again");
    robot_silent_ = false;
  } else if (!robot_silent_ && secondsWithoutNewFrame() > kSilentRobotS) {
    robot_silent_ = true;
    spdlog::warn("operator view: no new camera frame from the robot at {} for {:.1f} s{}",
                 options_.endpoints.connect(0), secondsWithoutNewFrame(),
                 hasImage() ? " (showing the last one)" : " (is telesphere-robot running?)");
  }
  return true;
}

void OperatorView::keepMediaSession() {
  // A keyed link's media path opens only with a session key from the robot, asked for over the
  // authenticated control channel (DESIGN.md §10). Asked again when the robot restarted (a new
  // process has a new key), and when no media frame came for 3 s while the robot is heard (the
  // seat was handed over and back, another session took the key): at most every 2 s.
  if (!media_ || !options_.endpoints.credentials.secure()) return;
  const link::LinkActivity activity = client_.activity();
  if (activity.robot_instance == 0 || media_session_in_flight_) return;
  const std::int64_t now = link::linkNowNs();
  const bool restarted = media_session_instance_ != activity.robot_instance;
  const bool silent = media_->hasSealKey() && now - last_new_frame_ns_ > 3'000'000'000;
  if (media_->hasSealKey() && !restarted && !silent) return;
  if (now - media_session_requested_ns_ < 2'000'000'000) return;
  media_session_requested_ns_ = now;
  media_session_in_flight_ = true;
  const std::uint64_t instance = activity.robot_instance;
  link::proto::ControlRequest request;
  request.set_open_media_session(true);
  control_.send(std::move(request), [this, instance](const std::optional<link::proto::ControlReply>& reply) {
    media_session_in_flight_ = false;
    if (!reply || !reply->ok() || reply->media_session_key().size() != link::media::MediaSealKey().size()) {
      spdlog::warn("operator view: no media session key from the robot: {}",
                   !reply ? std::string("no reply within 2 s") : reply->ok() ? "no key in the reply" : reply->error());
      return;
    }
    link::media::MediaSealKey key;
    std::copy(reply->media_session_key().begin(), reply->media_session_key().end(), key.begin());
    media_->setSealKey(key);
    media_session_instance_ = instance;
  });
}

void OperatorView::followRobotCalibration(const link::proto::RobotState& state) {
  const std::uint64_t generation = state.calibration_generation();
  if (generation == 0 || generation == stats_.calibration_generation) return;
  {
    std::lock_guard lock(control_result_mutex_);
    if (fetched_calibration_ && fetched_calibration_->generation == generation) return;
  }
  // One request at a time; asked again when no answer came (the reply's handler clears it), after
  // 3 s, and after a refusal later each time (up to a minute: a replaying robot that holds no
  // calibration refuses for good, and asking every 3 s would only fill the log).
  if (calibration_requested_ == generation && frame_begin_ns_ - calibration_requested_ns_ < calibration_retry_ns_.load())
    return;
  calibration_requested_ = generation;
  calibration_requested_ns_ = frame_begin_ns_;
  link::proto::ControlRequest request;
  request.set_get_calibration(true);
  control_.send(std::move(request), [this](const std::optional<link::proto::ControlReply>& reply) {
    if (!reply || !reply->ok() || !reply->has_calibration()) {
      const std::int64_t retry = calibration_retry_ns_.load();
      if (reply && !reply->ok()) calibration_retry_ns_ = std::min<std::int64_t>(2 * retry, 60'000'000'000);
      spdlog::warn("operator view: the robot's calibration: {} (asking again in {:.0f} s)",
                   !reply ? std::string("no reply within 2 s") : reply->ok() ? "no calibration in the reply" : reply->error(),
                   double(calibration_retry_ns_.load()) * 1e-9);
      return;
    }
    calibration_retry_ns_ = kCalibrationRetryNs;
    auto parsed = calib::parseCalibration(reply->calibration().yaml(), "robot calibration");
    if (!parsed || parsed->cameras.size() != 2) {
      spdlog::warn("operator view: the robot's calibration generation {} is unusable: {}",
                   reply->calibration().generation(),
                   parsed ? std::string("not two cameras") : parsed.error().describe());
      return;
    }
    std::lock_guard lock(control_result_mutex_);
    fetched_calibration_ = FetchedCalibration{reply->calibration().generation(), std::move(*parsed),
                                              reply->calibration().source()};
  });
}

bool OperatorView::takeFetchedCalibration(const video::DecodedStereoFrame* frame, std::string* error) {
  std::optional<FetchedCalibration> fetched;
  {
    std::lock_guard lock(control_result_mutex_);
    if (!fetched_calibration_) return true;
    // Poses and intrinsics of one frame belong together: wait for a frame the robot stamped with it
    // (a robot that restarted counts from 1 again: any other generation than the one shown).
    const std::uint64_t frame_generation = frame ? frame->frame.calibration_generation() : 0;
    if (frame && frame_generation != 0 && frame_generation != fetched_calibration_->generation) return true;
    fetched.swap(fetched_calibration_);
  }
  if (!renderer_.setCalibration(fetched->calibration, error)) return false;
  if (depth_) {  // the sweep's sample positions follow the calibration; the old depth goes with it
    depth_ = std::make_unique<DepthWorker>(fetched->calibration, options_.depth);
    renderer_.setDepth(options_.depth_proxy, nullptr);
  }
  if (stats_.calibration_generation != 0 || fetched->generation != 1)
    spdlog::info("operator view: calibration generation {} from the robot ({})", fetched->generation, fetched->source);
  stats_.calibration_generation = fetched->generation;
  ++stats_.calibration_changes;
  calibration_requested_ = 0;
  return true;
}

std::shared_ptr<const video::DecodedStereoFrame> OperatorView::frameToShow() {
  auto newest = decoder_.newest();
  const auto& current = renderer_.frame();
  if (!newest || newest == current) return newest;
  if (cameraPosesMeasured(newest->frame)) {
    if (unmeasured_since_ns_ >= 0)
      spdlog::info("operator view: camera poses are measured again (joint states from the robot)");
    unmeasured_since_ns_ = -1;
    holding_measured_ = showing_unmeasured_ = false;
    render::RenderSettings settings = renderer_.settings();
    settings.image_gain = 1.0f;
    renderer_.setSettings(settings);
    return newest;
  }
  if (unmeasured_since_ns_ < 0) {
    unmeasured_since_ns_ = frame_begin_ns_;
    spdlog::warn("operator view: the robot's camera frames carry no measured camera pose (no joint "
                 "state at their capture time); {}",
                 current && !showing_unmeasured_ ? "holding the last measured frame, then showing them dimmed"
                                                 : "showing them dimmed");
  }
  const bool can_hold = current && !showing_unmeasured_ &&
                        double(frame_begin_ns_ - unmeasured_since_ns_) * 1e-9 < options_.hold_measured_s;
  if (can_hold) {
    if (newest->frame.sequence() != last_unmeasured_sequence_) ++stats_.unmeasured_frames_held_back;
    last_unmeasured_sequence_ = newest->frame.sequence();
    holding_measured_ = true;
    return current;
  }
  holding_measured_ = false;
  showing_unmeasured_ = true;
  ++stats_.unmeasured_frames_shown;
  render::RenderSettings settings = renderer_.settings();
  settings.image_gain = kUnmeasuredGain;
  renderer_.setSettings(settings);
  return newest;
}

std::shared_ptr<const video::DecodedStereoFrame> OperatorView::holdForOwnDepth(
    std::shared_ptr<const video::DecodedStereoFrame> next, std::shared_ptr<const video::DecodedStereoFrame> current) {
  depth_->offer(next);  // a pair of the sequence offered last is ignored: it is swept once
  if (!current) return next;  // nothing on show to hold instead
  const auto estimate = depth_->newest();
  if (depth_hold_since_ns_ < 0) depth_hold_since_ns_ = frame_begin_ns_;
  // The wait runs from the first newer image, not per image: a stream that outpaces the sweep
  // must not keep the view on the old image for ever.
  const double waited_ms = double(frame_begin_ns_ - depth_hold_since_ns_) * 1e-6;
  const bool own = estimate && estimate->frame_sequence == next->frame.sequence();
  if (!own && waited_ms < options_.depth_hold_ms) return current;
  if (own)
    ++stats_.depth_images_held;
  else
    ++stats_.depth_hold_timeouts;
  depth_hold_ms_.add(waited_ms);
  depth_hold_since_ns_ = -1;
  return next;
}

bool OperatorView::renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view,
                             GLuint framebuffer, std::string* error) {
  if (!stats_.nominal_from_robot && !T_robot_vr_stand_in_ && eye == 0 && renderer_.frame()) {
    // No nominal pose yet: the left eye looks along the left camera's axis from its centre.
    T_robot_vr_stand_in_ = standInT_robot_vr(renderer_.frame()->frame, T_vr_eye);
    T_robot_vr_ = *T_robot_vr_stand_in_;
  }
  if (eye == 0 && renderer_.frame() && stats_.nominal_from_robot) {
    // Δs: where the left eye is against where the left camera was when the image was taken.
    const Eigen::Vector3d p_robot_eye = T_robot_vr_ * T_vr_eye.translation();
    const auto& t = renderer_.frame()->frame.left().t_robot_cam();
    telemetry_frame_.set_eye_camera_distance_m((p_robot_eye - Eigen::Vector3d(t.tx(), t.ty(), t.tz())).norm());
    // Behind only where the head follows in 6D: in the other modes the eye leaves the camera by design.
    if (renderer_.settings().mode == link::VisualMode::kFull6d)
      link_state_.eye_camera_distance_m = telemetry_frame_.eye_camera_distance_m();
  }
  if (!renderer_.renderEye(eye, T_robot_vr_, T_vr_eye, view, framebuffer, error)) return false;
  drawLinkState(framebuffer, view.width, view.height, link_state_, options_.link_state);
  if (eye == 0) {
    const Staleness staleness = stalenessOf(link_state_.image_age_ms, options_.link_state);
    if (staleness == Staleness::kTinted) ++stats_.frames_tinted;
    if (staleness == Staleness::kStale) ++stats_.frames_stale;
    if (!link_state_.stream_text.empty()) ++stats_.frames_stream_below_nominal;
    if (robotBehind(link_state_, options_.link_state)) ++stats_.frames_robot_behind;
  }
  if (trial_.running()) {
    drawTrialIndicator(framebuffer, view.width, view.height, trial_.elapsed_s(), trial_.time_limit_s());
    if (eye == 0) telemetry_frame_.set_trial_indicator_shown(true);
  }
  return true;
}

void OperatorView::endFrame(std::int64_t shown_ns, double render_ms, std::uint64_t missed_frames) {
  ++stats_.frames;
  render_ms_.add(render_ms);
  render_ms_last_second_.push_back(render_ms);
  if (const auto& frame = renderer_.frame()) {
    ++stats_.frames_with_image;
    if (uploaded_this_frame_ns_ >= 0) {
      ++stats_.stereo_frames_shown;
      upload_ms_.add(renderer_.lastUploadMs());
    }
    const std::int64_t capture_robot = frame->frame.stamps().capture_ns();
    const std::int64_t capture = client_.clock().serverToClient(capture_robot).value_or(capture_robot);
    const double age_ms = double(shown_ns - capture) * 1e-6;
    age_ms_.add(age_ms);
    age_ms_last_second_.push_back(age_ms);
    telemetry_frame_.set_stereo_sequence(frame->frame.sequence());
    if (uploaded_this_frame_ns_ >= 0) {
      telemetry_frame_.set_new_image(true);
      link::proto::StageStamps* stamps = telemetry_frame_.mutable_stamps();
      *stamps = frame->frame.stamps();
      stamps->set_uploaded_ns(uploaded_this_frame_ns_);
      stamps->set_displayed_ns(shown_ns);
    }
  }
  telemetry_frame_.set_pose_unmeasured(showing_unmeasured_);
  telemetry_frame_.set_holding_measured(holding_measured_);
  telemetry_frame_.set_render_ms(render_ms);
  telemetry_frame_.set_missed(static_cast<std::uint32_t>(missed_frames - std::min(missed_frames, missed_at_last_frame_)));
  missed_at_last_frame_ = missed_frames;
  *telemetry_.add_frames() = telemetry_frame_;

  const std::int64_t now = link::linkNowNs();
  if (now - last_telemetry_ns_ >= kTelemetryPeriodNs) {
    telemetry_.set_batch(telemetry_.batch() + 1);
    if (const auto clock = client_.clock().estimate()) {
      telemetry_.set_clock_synced(true);
      telemetry_.set_robot_to_xr_offset_ns(clock->server_to_client_offset_ns);
      telemetry_.set_round_trip_ns(clock->round_trip_ns);
    } else {
      telemetry_.set_clock_synced(false);
    }
    telemetry_.set_missed_total(missed_frames);
    telemetry_.set_visual_mode(link::toProto(renderer_.settings().mode));
    telemetry_.set_sphere_radius(renderer_.settings().radius);
    telemetry_.set_calibration_generation(stats_.calibration_generation);
    fillDepthState(now, telemetry_.mutable_depth());
    if (media_) {
      const auto m = media_->stats();
      link::proto::MediaReceiveCounts* counts = telemetry_.mutable_media();
      counts->set_t_ns(now);
      counts->set_datagrams(m.datagrams);
      counts->set_frames_whole(m.assembler.frames_whole);
      counts->set_frames_concealed(m.assembler.frames_concealed);
      counts->set_frames_lost(m.assembler.frames_lost + m.assembler.frames_malformed);
      counts->set_bands_concealed(m.assembler.bands_lost);
      counts->set_chunks_repaired(m.assembler.chunks_recovered);
    }
    client_.sendXrTelemetry(telemetry_);
    telemetry_.clear_frames();
    last_telemetry_ns_ = now;
  }

  // Statistics for the console, once a second, over the last second.
  if (last_stats_ns_ == 0) last_stats_ns_ = now;
  if (now - last_stats_ns_ >= 1'000'000'000) {
    link::proto::XrStats xr_stats;
    xr_stats.set_t_ns(now);
    xr_stats.set_fps(double(stats_.frames - frames_at_last_stats_) / (double(now - last_stats_ns_) * 1e-9));
    const video::LatencyFigure age = video::latencyFigure(std::move(age_ms_last_second_));
    const video::LatencyFigure render = video::latencyFigure(std::move(render_ms_last_second_));
    xr_stats.set_render_ms(render.p50_ms);
    xr_stats.set_missed_frames(missed_frames);
    xr_stats.set_image_age_p50_ms(age.p50_ms);
    xr_stats.set_image_age_p99_ms(age.p99_ms);
    client_.sendXrStats(xr_stats);
    last_stats_ns_ = now;
    frames_at_last_stats_ = stats_.frames;
    age_ms_last_second_.clear();  // moved from: valid, and empty after clear()
    render_ms_last_second_.clear();
  }
}

void OperatorView::setDepthProxy(link::DepthProxy proxy) {
  if (proxy == options_.depth_proxy) return;
  spdlog::info("operator view: scene proxy {} (was {})", link::depthProxyName(proxy), link::depthProxyName(options_.depth_proxy));
  switchDepthProxy(proxy);
}

void OperatorView::switchDepthProxy(link::DepthProxy proxy) {
  options_.depth_proxy = proxy;
  if (proxy != link::DepthProxy::kFixed && !depth_) depth_ = std::make_unique<DepthWorker>(renderer_.calibration(), options_.depth);
  renderer_.setDepth(proxy, depth_ ? depth_->newest() : nullptr);
}

void OperatorView::requestDepthProxy(link::DepthProxy proxy) {
  if (!options_.follow_robot_settings || !client_.latestRobotState()) return setDepthProxy(proxy);
  link::proto::ControlRequest request;
  request.set_set_depth_proxy(link::toProto(proxy));
  sendControl(std::move(request), "set_depth_proxy " + std::string(link::depthProxyName(proxy)));
}

void OperatorView::fillDepthState(std::int64_t now_ns, link::proto::DepthProxyState* out) const {
  out->Clear();
  out->set_t_ns(now_ns);
  out->set_proxy(link::toProto(options_.depth_proxy));
  out->set_estimate_age_ms(-1.0);
  const std::shared_ptr<const DepthEstimate>& estimate = renderer_.depth();  // the one in use
  for (int i = 0; i < 2; ++i)
    out->add_radius_m(options_.depth_proxy == link::DepthProxy::kFixed || !estimate ? renderer_.settings().radius
                                                                                     : estimate->radius_m[i]);
  if (!depth_) return;
  const DepthWorkerStats stats = depth_->stats();
  out->set_estimates(stats.estimated);
  out->set_pairs_skipped(stats.skipped);
  if (!estimate) return;
  for (int i = 0; i < 2; ++i) {
    out->add_matched_fraction(estimate->matched_fraction[i]);
    out->add_motion_views(estimate->motion_views[i]);
    out->add_motion_baseline_m(estimate->motion_baseline_m[i]);
    out->add_tiles_decided_by_motion(estimate->tiles_decided_by_motion[i]);
  }
  const std::int64_t capture = client_.clock().serverToClient(estimate->capture_ns).value_or(estimate->capture_ns);
  out->set_estimate_age_ms(double(now_ns - capture) * 1e-6);
  out->set_sweep_ms(estimate->sweep_ms);
  out->set_estimate_sequence(estimate->frame_sequence);
}

void addDepthFigures(link::DepthProxy proxy, const DepthWorker* worker, OperatorViewStats* out) {
  out->depth_proxy = std::string(link::depthProxyName(proxy));
  if (!worker) return;
  const DepthWorkerStats depth = worker->stats();
  out->depth_estimates = depth.estimated;
  out->depth_pairs_skipped = depth.skipped;
  out->depth_sweep_ms = depth.last_sweep_ms;
  out->depth_gpu_unavailable = depth.gpu_unavailable;
  if (const auto estimate = worker->newest()) {
    out->depth_sweep_on_gpu = estimate->pair_costs_on_gpu;
    out->depth_radius_left_m = estimate->radius_m[0];
    out->depth_matched_fraction = estimate->matched_fraction[0];
    out->depth_motion_views_left = estimate->motion_views[0];
    out->depth_motion_baseline_left_m = estimate->motion_baseline_m[0];
    out->depth_tiles_decided_by_motion_left = estimate->tiles_decided_by_motion[0];
  }
}

OperatorViewStats OperatorView::stats() const {
  OperatorViewStats out = stats_;
  addDepthFigures(options_.depth_proxy, depth_.get(), &out);
  const video::LatencyFigure held = depth_hold_ms_.figure();
  out.depth_hold_ms_p50 = held.p50_ms;
  out.depth_hold_ms_p99 = held.p99_ms;
  const video::LatencyFigure render = render_ms_.figure(), age = age_ms_.figure();
  out.render_ms_p50 = render.p50_ms;
  out.render_ms_p99 = render.p99_ms;
  out.image_age_p50_ms = age.p50_ms;
  out.image_age_p99_ms = age.p99_ms;
  const video::LatencyFigure upload = upload_ms_.figure();
  out.upload_ms_render_thread_p50 = upload.p50_ms;
  out.upload_ms_render_thread_p99 = upload.p99_ms;
  const video::StereoDecodeStats decoded = decoder_.stats();
  out.decode_ms_p50 = decoded.decode.p50_ms;
  out.images_in_upload_slots = decoded.images_in_upload_slots;
  out.images_in_own_memory = decoded.images_in_own_memory;
  out.pose_to_display_ms_p50 = pose_lead_ms_.figure().p50_ms;
  out.frames_concealed = decoded.frames_concealed;
  out.rows_concealed = decoded.rows_concealed;
  out.rows_grey = decoded.rows_grey;
  out.video_codec = decoded.codec;
  out.key_frames_requested = decoded.key_frames_requested;
  out.frames_awaiting_key_frame = decoded.dropped(video::FrameDropReason::kAwaitingKeyFrame);
  if (media_) {
    const auto m = media_->stats();
    out.video_link = "udp";
    out.media_datagrams = m.datagrams;
    out.media_frames_whole = m.assembler.frames_whole;
    out.media_frames_concealed = m.assembler.frames_concealed;
    out.media_frames_lost = m.assembler.frames_lost + m.assembler.frames_malformed;
    out.media_bands_lost = m.assembler.bands_lost;
    out.media_chunks_fec = m.assembler.chunks_recovered;
    out.media_chunks_requested = m.assembler.chunks_requested;
    out.media_chunks_repaired = m.assembler.chunks_repaired;
    out.media_frames_superseded = m.assembler.frames_superseded;
  }
  return out;
}

void OperatorView::requestCaptureNominal() {
  link::proto::ControlRequest request;
  request.set_capture_nominal(true);
  sendControl(std::move(request), "capture_nominal");
}

void OperatorView::requestMode(link::VisualMode mode) {
  link::proto::ControlRequest request;
  request.set_set_visual_mode(link::toProto(mode));
  sendControl(std::move(request), "set_mode " + std::string(link::visualModeName(mode)));
}

void OperatorView::requestRadius(double radius_m) {
  link::proto::ControlRequest request;
  request.set_set_sphere_radius(radius_m);
  sendControl(std::move(request), "set_sphere_radius " + std::to_string(radius_m));
}

void OperatorView::requestRadiusScaled(double factor) {
  requestRadius(std::clamp(settings().radius * factor, link::kMinSphereRadius, link::kMaxSphereRadius));
}

std::string OperatorView::lastControlResult() const {
  std::lock_guard lock(control_result_mutex_);
  return last_control_result_;
}

bool OperatorView::calibrationPending() const {
  std::lock_guard lock(control_result_mutex_);
  return fetched_calibration_.has_value();
}

void OperatorView::sendControl(link::proto::ControlRequest request, std::string what) {
  control_.send(std::move(request), [this, what](const std::optional<link::proto::ControlReply>& reply) {
    std::string result;
    if (!reply) {
      result = what + ": no reply from the robot within 2 s (is telesphere-robot running?)";
      spdlog::warn("operator view: {}", result);
    } else if (!reply->ok()) {
      result = what + ": refused: " + reply->error();
      spdlog::warn("operator view: {}", result);
    } else {
      result = what + ": ok";
      spdlog::info("operator view: {}", result);
    }
    std::lock_guard lock(control_result_mutex_);
    last_control_result_ = result;
  });
}

}  // namespace telesphere::xr::frame_loop
