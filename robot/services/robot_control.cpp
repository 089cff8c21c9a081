// SPDX-License-Identifier: MIT
/// @brief RobotControl: dispatch and settings.
#include "robot/services/robot_control.h"

#include "robot/link/proto_enums.h"

#include <cmath>
#include <map>
#include <string>

namespace telesphere::robot::services {

link::proto::ControlReply RobotControl::handle(const link::proto::ControlRequest& request) {
  // The head loop's lease clock stands while the robot serves a request (a still may take longer
  // than a calibration hold's lease, and the holder cannot renew meanwhile).
  struct Serving {
    head::HeadLoop& loop;
    explicit Serving(head::HeadLoop& l) : loop(l) { loop.controlStarted(); }
    ~Serving() { loop.controlFinished(); }
  } serving(loop_);
  link::proto::ControlReply reply;
  if (request.request_case() == link::proto::ControlRequest::kSetJpegQuality) {
    reply.set_id(request.id());
    const int q = request.set_jpeg_quality();
    if (!video_) {
      reply.set_error("no video path on this robot");
    } else if (q < 1 || q > 100) {
      reply.set_error("JPEG quality " + std::to_string(q) + " is outside [1, 100]");
    } else {
      video::JpegSettings settings = video_->jpegSettings();
      settings.quality = q;
      video_->setJpegSettings(settings);
      reply.set_ok(true);
    }
  } else if (request.request_case() == link::proto::ControlRequest::kSetMediaCapMbit) {
    reply.set_id(request.id());
    const double cap_mbit = request.set_media_cap_mbit();
    link::media::MediaSender* media = video_ ? video_->mediaSender() : nullptr;
    if (!media) {
      reply.set_error("this robot serves no media path (started with --no-media or without cameras)");
    } else if (!std::isfinite(cap_mbit) || cap_mbit < 0) {
      reply.set_error("a cap must be a finite rate ≥ 0 Mbit/s (0 lifts it), not " + std::to_string(cap_mbit));
    } else if (cap_mbit > 0 && cap_mbit < kMinMediaCapMbit) {
      reply.set_error("a cap under 0.5 Mbit/s (the send-rate controller's floor) leaves no room for video");
    } else {
      media->setCapBps(cap_mbit * 1e6);
      reply.set_ok(true);
    }
  } else if (request.request_case() == link::proto::ControlRequest::kRequestKeyFrame) {
    // The operator's H.264/HEVC decoder lost a frame: both cameras' next images are key frames.
    reply.set_id(request.id());
    if (!video_)
      reply.set_error("no video path on this robot");
    else if (!video_->requestKeyFrame())
      reply.set_error("this robot sends MJPEG: every image is a key frame");
    else
      reply.set_ok(true);
  } else if (request.request_case() == link::proto::ControlRequest::kSetVideoCodec) {
    // The supervisor's choice of codec (#34), from the next pair on.
    reply.set_id(request.id());
    const auto codec = link::fromProto(request.set_video_codec());
    if (!video_) {
      reply.set_error("no video path on this robot");
    } else if (!codec) {
      reply.set_error("codec " + std::to_string(int(request.set_video_codec())) + " is not one this robot knows");
    } else {
      video_->setCodec(*codec);
      reply.set_ok(true);
    }
  } else if (request.request_case() == link::proto::ControlRequest::kOpenMediaSession) {
    // A keyed link's media path (DESIGN.md §10): a fresh key for this session, handed over the
    // authenticated control channel (the link checked who asks); the session before it ends.
    reply.set_id(request.id());
    link::media::MediaSender* media = video_ ? video_->mediaSender() : nullptr;
    if (!media) {
      reply.set_error("this robot serves no media path (started with --no-media or without cameras)");
    } else {
      const link::media::MediaSealKey key = link::media::newMediaSealKey();
      media->setSealKey(key);
      reply.set_media_session_key(key.data(), key.size());
      reply.set_ok(true);
    }
  } else if (request.request_case() == link::proto::ControlRequest::kCalibrationCapture) {
    reply.set_id(request.id());
    std::string error;
    if (!stills_)
      reply.set_error("no cameras on this robot: no calibration stills");
    else if (stills_->take(reply.mutable_still(), still_timeout_, &error))
      reply.set_ok(true);
    else
      reply.set_error(error);
    if (!reply.ok()) reply.clear_still();
  } else if (request.request_case() == link::proto::ControlRequest::kApplyCalibration ||
             request.request_case() == link::proto::ControlRequest::kRevertCalibration ||
             request.request_case() == link::proto::ControlRequest::kGetCalibration) {
    if (calibration_) {
      reply = calibration_->handleControl(request);
    } else {
      reply.set_id(request.id());
      reply.set_error("this robot's calibration is fixed (no live apply)");
    }
  } else if (request.request_case() == link::proto::ControlRequest::kRecording) {
    reply.set_id(request.id());
    std::string error;
    const auto& r = request.recording();
    if (!recording_) {
      reply.set_error("this robot cannot record");
    } else if (r.start() ? recording_->startNamed(r.name(), &error) : recording_->stop(&error)) {
      reply.set_ok(true);
      trial_recording_ = false;  // the supervisor's now (or none): a trial's end does not stop it
    } else {
      reply.set_error(error);
    }
    if (recording_) *reply.mutable_recording() = recording_->state();
  } else {
    reply = loop_.handleControl(request);
    if (request.request_case() == link::proto::ControlRequest::kSetTrialIndicator && reply.ok() && recording_)
      followTrial(request.set_trial_indicator(), &reply);
  }
  fillSettings(reply.mutable_settings());
  return reply;
}

void RobotControl::followTrial(const link::proto::TrialIndicator& trial, link::proto::ControlReply* reply) {
  std::string error;
  if (trial.running() && !trial.recording_name().empty() && recording_->available()) {
    // A trial recording whose trial never ended (the console went away) ends here; a recording
    // the supervisor started goes on through the trial (it holds the trial too).
    if (trial_recording_ && recording_->active()) {
      std::string ignored;
      recording_->stop(&ignored);
      trial_recording_ = false;
    }
    if (!recording_->active()) {
      // The file says which trial it holds, without the study database.
      std::map<std::string, std::string> metadata{{"study", trial.study()},
                                                  {"participant", trial.participant()},
                                                  {"trial_id", std::to_string(trial.trial_id())},
                                                  {"mode", trial.mode()},
                                                  {"study_database", trial.study_database()}};
      std::erase_if(metadata, [](const auto& kv) { return kv.second.empty() || kv.second == "0"; });
      if (recording_->startNamed(trial.recording_name(), &error, metadata))
        trial_recording_ = true;
      else
        reply->set_error("the trial runs, but is not recorded: " + error);  // ok stays: the trial is on
    }
  } else if (!trial.running() && trial_recording_) {
    trial_recording_ = false;
    if (!recording_->stop(&error)) reply->set_error("the trial's recording: " + error);
  }
  *reply->mutable_recording() = recording_->state();
}

void RobotControl::fillSettings(link::proto::RobotSettings* settings) const {
  loop_.fillSettings(settings);
  if (!video_) return;
  const video::JpegSettings jpeg = video_->jpegSettings();
  settings->set_jpeg_quality(jpeg.quality);
  settings->set_jpeg_subsampling(link::toProto(jpeg.subsampling));
  settings->set_video_codec(link::toProto(video_->codec()));
  if (video_->codec() != link::VideoCodec::kMjpeg) {
    settings->set_video_mbit(static_cast<double>(video_->videoBitRateBps()) * 1e-6);
    settings->set_video_encoder(video_->stats().video.backend);
  }
  if (const link::media::MediaSender* media = video_->mediaSender()) {
    settings->set_media_path(true);
    settings->set_media_cap_mbit(media->capBps() * 1e-6);
  }
}

}  // namespace telesphere::robot::services
