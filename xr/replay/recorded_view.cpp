// SPDX-License-Identifier: MIT
/// @brief RecordedView (see recorded_view.h).
#include "xr/replay/recorded_view.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "robot/link/link_pose.h"
#include "robot/link/link_schema.h"
#include "robot/link/proto_enums.h"
#include "calib/calibration_file.h"
#include "xr/frame_loop/robot_view_state.h"
#include "xr/frame_loop/trial_indicator.h"
#include "xr/video/latency_figure.h"

namespace telesphere::xr::replay {
namespace {

/// Both JPEGs of `recorded` into planes of their own; nothing (the reason in *error) when one fails.
std::shared_ptr<const video::DecodedStereoFrame> decodePair(video::JpegDecoder& decoder, record::RecordedFrame& recorded,
                                                     std::string* error) {
  auto decoded = std::make_shared<video::DecodedStereoFrame>();
  const link::proto::CameraImage* images[2] = {&recorded.frame.left(), &recorded.frame.right()};
  const std::vector<std::uint8_t>* jpegs[2] = {recorded.left.get(), recorded.right.get()};
  for (int side = 0; side < 2; ++side) {
    auto planes = std::make_shared<render::YuvPlanes>();
    const auto result = decoder.decode(*jpegs[side], static_cast<int>(images[side]->width()),
                                       static_cast<int>(images[side]->height()),
                                       static_cast<int>(link::kMaxImageSide), *planes, error);
    if (result != video::JpegDecodeError::kNone) {
      *error = std::string(side == 0 ? "left" : "right") + " image of frame " +
               std::to_string(recorded.frame.sequence()) + ": " + video::jpegDecodeErrorName(result) + ": " + *error;
      return nullptr;
    }
    (side == 0 ? decoded->left : decoded->right) = std::move(planes);
  }
  decoded->frame = std::move(recorded.frame);
  return decoded;
}

}  // namespace

RecordedView::RecordedView(const calib::SystemCalibration& calibration, const render::RenderSettings& render,
                           bool follow_recorded_settings, bool follow_recorded_calibrations,
                           std::uint64_t calibration_generation, link::DepthProxy depth_proxy,
                           const frame_loop::DepthWorkerOptions& depth)
    : renderer_(calibration, render, 0),
      follow_settings_(follow_recorded_settings),
      follow_calibrations_(follow_recorded_calibrations),
      depth_proxy_(depth_proxy),
      depth_options_(depth) {
  stats_.calibration_generation = calibration_generation;
}

bool RecordedView::takeCalibration(const record::RecordedCalibration& recorded, std::string* error) {
  auto parsed = calib::parseCalibration(recorded.yaml, "the recording's calibration generation " +
                                                           std::to_string(recorded.generation));
  if (!parsed || parsed->cameras.size() != 2) {
    *error = parsed ? "the recording's calibration generation " + std::to_string(recorded.generation) +
                          " does not have two cameras"
                    : parsed.error().describe();
    return false;
  }
  calibrations_[recorded.generation] = std::move(*parsed);
  return true;
}

void RecordedView::takeFrame(record::RecordedFrame&& frame) {
  const auto codec = link::fromProto(frame.frame.left().codec());
  if (codec && *codec != link::VideoCodec::kMjpeg && frame.frame.right().codec() == frame.frame.left().codec()) {
    const auto decode_start = std::chrono::steady_clock::now();
    auto decoded = decodeVideoPair(frame, *codec);
    if (!decoded) return;  // counted; the pair before stays pending or on show
    decode_ms_.add(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - decode_start).count() / 2);
    if (pending_ || pending_decoded_) ++replaced_unshown_;
    pending_.reset();
    pending_decoded_ = std::move(decoded);
    return;
  }
  if (pending_ || pending_decoded_) ++replaced_unshown_;
  pending_decoded_.reset();
  pending_ = std::move(frame);
}

std::shared_ptr<const video::DecodedStereoFrame> RecordedView::decodeVideoPair(record::RecordedFrame& recorded,
                                                                               link::VideoCodec codec) {
  for (auto& decoder : video_)
    if (!decoder || decoder->codec() != codec) decoder = std::make_unique<video::VideoStreamDecoder>(codec, 1);
  auto decoded = std::make_shared<video::DecodedStereoFrame>();
  const link::proto::CameraImage* images[2] = {&recorded.frame.left(), &recorded.frame.right()};
  const std::vector<std::uint8_t>* bytes[2] = {recorded.left.get(), recorded.right.get()};
  bool awaiting = false;
  std::string why;
  for (int side = 0; side < 2; ++side) {
    auto planes = std::make_shared<render::YuvPlanes>();
    video::DecodeResult result;
    video_[side]->decode(video_[side]->reserve(recorded.frame.sequence()), *bytes[side], images[side]->key_frame(),
                         static_cast<int>(images[side]->width()), static_cast<int>(images[side]->height()), *planes,
                         result);
    if (result.error == video::JpegDecodeError::kNone)
      (side == 0 ? decoded->left : decoded->right) = std::move(planes);
    else if (result.awaiting_key_frame)
      awaiting = true;
    else if (why.empty())
      why = std::string(side == 0 ? "left" : "right") + " image: " + result.message;
  }
  if (decoded->left && decoded->right) {
    decoded->frame = std::move(recorded.frame);
    return decoded;
  }
  if (!why.empty()) {
    if (undecodable_++ == 0)
      spdlog::warn("replay: frame {}: {} (the previous frame stays on show)", recorded.frame.sequence(), why);
  } else if (awaiting) {
    ++awaiting_key_frame_;
  }
  return nullptr;
}

bool RecordedView::beginFrame(const Eigen::Isometry3d&, std::int64_t, bool, std::string* error) {
  if (!takePending(error)) return false;
  followDepthProxy();
  return true;
}

void RecordedView::followDepthProxy() {
  // What the operator's eyes had (the XR app's telemetry), else the session's choice.
  std::optional<link::DepthProxy> recorded = xr_depth_proxy_;
  if (!recorded && state_) recorded = link::fromProto(state_->depth_proxy());
  if (follow_settings_ && recorded && *recorded != depth_proxy_) {
    depth_proxy_ = *recorded;
    ++stats_.settings_changes;
  }
  if (depth_proxy_ != link::DepthProxy::kFixed && !depth_) {
    frame_loop::DepthWorkerOptions options = depth_options_;
    options.on_caller_thread = true;  // the same estimates run after run
    depth_ = std::make_unique<frame_loop::DepthWorker>(renderer_.calibration(), options);
  }
  if (depth_) depth_->offer(renderer_.frame());  // each pair swept once, when it is first shown
  renderer_.setDepth(depth_proxy_, depth_ ? depth_->newest() : nullptr);
}

void RecordedView::takeXrTelemetry(const link::proto::XrTelemetry& telemetry) {
  if (!telemetry.has_depth()) return;
  if (const auto proxy = link::fromProto(telemetry.depth().proxy())) xr_depth_proxy_ = proxy;
}

bool RecordedView::takePending(std::string* error) {
  if (state_ && state_->nominal_set()) {
    T_robot_vr_ = link::fromLinkPose(state_->t_robot_vr());
    stats_.nominal_from_robot = true;
  } else if (T_robot_vr_stand_in_) {
    T_robot_vr_ = *T_robot_vr_stand_in_;
  }
  if (state_ && follow_settings_) {
    const render::RenderSettings settings = frame_loop::withRobotSettings(renderer_.settings(), *state_);
    if (settings.mode != renderer_.settings().mode || settings.radius != renderer_.settings().radius) {
      renderer_.setSettings(settings);
      ++stats_.settings_changes;
    }
  }
  uploaded_this_frame_ = false;
  if (pending_decoded_) {
    const auto decoded = std::move(pending_decoded_);
    pending_decoded_.reset();
    return show(decoded, error);
  }
  if (!pending_) return true;
  record::RecordedFrame recorded = std::move(*pending_);
  pending_.reset();
  const auto decode_start = std::chrono::steady_clock::now();
  std::string why;
  const auto decoded = decodePair(decoder_, recorded, &why);
  if (!decoded) {
    if (undecodable_++ == 0) spdlog::warn("replay: {} (the previous frame stays on show)", why);
    return true;
  }
  decode_ms_.add(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - decode_start).count() / 2);
  return show(decoded, error);
}

bool RecordedView::show(const std::shared_ptr<const video::DecodedStereoFrame>& decoded, std::string* error) {
  // The frame's own calibration: poses and camera models of one frame belong together.
  const std::uint64_t generation = decoded->frame.calibration_generation();
  if (follow_calibrations_ && generation != 0 && generation != stats_.calibration_generation) {
    const auto it = calibrations_.find(generation);
    if (it != calibrations_.end()) {
      if (!renderer_.setCalibration(it->second, error)) return false;
      depth_.reset();  // the sweep's sample positions follow the calibration; the old depth goes with it
      renderer_.setDepth(depth_proxy_, nullptr);
      if (stats_.calibration_generation != 0) ++stats_.calibration_changes;
      stats_.calibration_generation = generation;
    }
  }
  render::RenderSettings settings = renderer_.settings();
  const bool measured = frame_loop::cameraPosesMeasured(decoded->frame);
  settings.image_gain = measured ? 1.0f : frame_loop::OperatorView::kUnmeasuredGain;
  renderer_.setSettings(settings);
  if (!measured) ++stats_.unmeasured_frames_shown;
  if (!renderer_.setFrame(decoded, error)) return false;
  uploaded_this_frame_ = true;
  stats_.images_in_own_memory += 2;
  return true;
}

bool RecordedView::renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView& view, GLuint framebuffer,
                             std::string* error) {
  if (!stats_.nominal_from_robot && !T_robot_vr_stand_in_ && eye == 0 && renderer_.frame()) {
    T_robot_vr_stand_in_ = frame_loop::standInT_robot_vr(renderer_.frame()->frame, T_vr_eye);
    T_robot_vr_ = *T_robot_vr_stand_in_;
  }
  if (!renderer_.renderEye(eye, T_robot_vr_, T_vr_eye, view, framebuffer, error)) return false;
  if (state_ && state_->trial().running())
    frame_loop::drawTrialIndicator(framebuffer, view.width, view.height, state_->trial().elapsed_s(), state_->trial().time_limit_s());
  if (link_cues_) frame_loop::drawLinkState(framebuffer, view.width, view.height, *link_cues_, {});
  return true;
}

void RecordedView::setLinkCues(const frame_loop::LinkState& state, float image_saturation) {
  link_cues_ = state;
  render::RenderSettings settings = renderer_.settings();
  settings.image_saturation = image_saturation;
  renderer_.setSettings(settings);
}

void RecordedView::endFrame(std::int64_t shown_ns, double render_ms, std::uint64_t) {
  ++stats_.frames;
  render_ms_.add(render_ms);
  if (const auto& frame = renderer_.frame()) {
    ++stats_.frames_with_image;
    age_ms_.add(double(shown_ns - frame->frame.stamps().capture_ns()) * 1e-6);
    if (uploaded_this_frame_) {
      ++stats_.stereo_frames_shown;
      upload_ms_.add(renderer_.lastUploadMs());
    }
  }
}

frame_loop::OperatorViewStats RecordedView::stats() const {
  frame_loop::OperatorViewStats out = stats_;
  const video::LatencyFigure render = render_ms_.figure(), age = age_ms_.figure();
  const video::LatencyFigure upload = upload_ms_.figure(), decode = decode_ms_.figure();
  out.render_ms_p50 = render.p50_ms;
  out.render_ms_p99 = render.p99_ms;
  out.image_age_p50_ms = age.p50_ms;
  out.image_age_p99_ms = age.p99_ms;
  out.upload_ms_render_thread_p50 = upload.p50_ms;
  out.upload_ms_render_thread_p99 = upload.p99_ms;
  out.decode_ms_p50 = decode.p50_ms;
  out.video_codec = video_[0] ? link::videoCodecName(video_[0]->codec()) : "mjpeg";
  out.frames_awaiting_key_frame = awaiting_key_frame_;
  frame_loop::addDepthFigures(depth_proxy_, depth_.get(), &out);
  return out;
}

}  // namespace telesphere::xr::replay
