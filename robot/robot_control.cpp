// SPDX-License-Identifier: MIT
/// @brief RobotControl: dispatch and settings.
#include "robot/robot_control.h"

#include "robot/link/proto_enums.h"

#include <string>

namespace telesphere::robot {

link::proto::ControlReply RobotControl::handle(const link::proto::ControlRequest& request) {
  link::proto::ControlReply reply;
  if (request.request_case() == link::proto::ControlRequest::kSetJpegQuality) {
    reply.set_id(request.id());
    const int q = request.set_jpeg_quality();
    if (!video_) {
      reply.set_error("no video path on this robot");
    } else if (q < 1 || q > 100) {
      reply.set_error("JPEG quality " + std::to_string(q) + " is outside [1, 100]");
    } else {
      JpegSettings settings = video_->jpegSettings();
      settings.quality = q;
      video_->setJpegSettings(settings);
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
  } else {
    reply = loop_.handleControl(request);
  }
  fillSettings(reply.mutable_settings());
  return reply;
}

void RobotControl::fillSettings(link::proto::RobotSettings* settings) const {
  loop_.fillSettings(settings);
  if (!video_) return;
  const JpegSettings jpeg = video_->jpegSettings();
  settings->set_jpeg_quality(jpeg.quality);
  settings->set_jpeg_subsampling(link::toProto(jpeg.subsampling));
}

}  // namespace telesphere::robot
