// SPDX-License-Identifier: MIT
/// @brief HeadLoop::handleControl: the link's control requests for the head, one case each (visual
///        mode, nominal pose, sphere radius, scene proxy, filter cut-off, jump threshold, arm stop and clear, the
///        study's trial indicator, calibration holds); every reply carries the head's settings.
#include "robot/head/head_loop.h"

#include <cmath>
#include <iostream>

#include "robot/link/proto_enums.h"
#include "robot/link/sphere_radius.h"

namespace telesphere::robot::head {

link::proto::ControlReply HeadLoop::handleControl(const link::proto::ControlRequest& request) {
  link::proto::ControlReply reply;
  reply.set_id(request.id());
  std::string error;
  bool ok = true;
  bool nominal = false;
  {
    std::lock_guard lock(mutex_);
    switch (request.request_case()) {
      case link::proto::ControlRequest::kSetVisualMode:
        if (const auto mode = link::fromProto(request.set_visual_mode())) {
          controller_.setMode(*mode);
        } else {
          ok = false;
          error = "unknown visual mode " + std::to_string(request.set_visual_mode()) +
                  " (full6d, orientation3d or fixed)";
        }
        break;
      case link::proto::ControlRequest::kCaptureNominal:
        nominal = true;
        if (!last_target_) {
          ok = false;
          error = "no head target received yet: put the headset on and try again";
        } else {
          pending_nominal_ = true;  // taken by the next tick, which has the newest joint state
        }
        break;
      case link::proto::ControlRequest::kNominalStep:
        nominal = true;
        ok = nominalStepLocked(request.nominal_step(), &error);
        break;
      case link::proto::ControlRequest::kSetSphereRadius: {
        const double r = request.set_sphere_radius();
        if (!link::acceptedSphereRadius(r)) {
          ok = false;
          error = "sphere radius " + std::to_string(r) + " m is outside [" +
                  std::to_string(link::kMinSphereRadius) + ", " + std::to_string(link::kMaxSphereRadius) + "]";
        } else {
          sphere_radius_ = r;
        }
        break;
      }
      case link::proto::ControlRequest::kSetDepthProxy:
        // The robot only holds the session's choice (each XR app renders with it); the depth
        // behind it is measured on the operator's side.
        if (const auto proxy = link::fromProto(request.set_depth_proxy())) {
          depth_proxy_ = *proxy;
        } else {
          ok = false;
          error = "unknown scene proxy " + std::to_string(request.set_depth_proxy()) + " (fixed, radius or grid)";
        }
        break;
      case link::proto::ControlRequest::kSetFilterCutoffHz: {
        const double f = request.set_filter_cutoff_hz();
        if (!(f > 0.0) || std::isnan(f)) {  // +inf is allowed: the filter is off
          ok = false;
          error = "filter cut-off " + std::to_string(f) + " Hz must be > 0 (inf: off)";
        } else {
          controller_.setCutoffHz(f);
        }
        break;
      }
      case link::proto::ControlRequest::kSetJumpThreshold: {
        const double p = request.set_jump_threshold().position_m();
        const double a = request.set_jump_threshold().angle_deg();
        if (!(std::isfinite(p) && p > 0.0 && p <= 2.0 && std::isfinite(a) && a > 0.0 && a <= 180.0)) {
          ok = false;
          error = "jump threshold " + std::to_string(p) + " m / " + std::to_string(a) +
                  "° is outside (0, 2] m / (0, 180]°";
        } else {
          controller_.setJumpThreshold(p, a * M_PI / 180.0);
        }
        break;
      }
      case link::proto::ControlRequest::kArmStop:
        stopped_by_console_ = true;
        if (recovery_.running())
          stop_after_recovery_ = true;  // the recovery owns the arm; the stop follows it at once
        else
          arm_.stop();
        std::cerr << "telesphere-robot: arm stopped from the console\n";
        break;
      case link::proto::ControlRequest::kClearFault:
        // Answered at once: the recovery runs on its own thread and the state shows its outcome.
        followArmLocked(clock_.nowNs());  // the outcome of an earlier recovery, if not taken yet
        if (armOkLocked()) break;         // nothing to clear
        if (recovery_.running() || recovery_.start()) {
          reply.set_pending(true);
          std::cerr << "telesphere-robot: clearing the arm's fault\n";
        }
        break;
      case link::proto::ControlRequest::kGetSettings:
        break;
      case link::proto::ControlRequest::kSetTrialIndicator: {
        const auto& t = request.set_trial_indicator();
        if (!(std::isfinite(t.elapsed_s()) && t.elapsed_s() >= 0.0 && std::isfinite(t.time_limit_s()) &&
              t.time_limit_s() >= 0.0)) {
          ok = false;
          error = "trial indicator: elapsed and time limit must be finite and ≥ 0 s";
        } else {
          trial_ = t;
          trial_received_ns_ = clock_.nowNs();
        }
        break;
      }
      case link::proto::ControlRequest::kCalibrationHeadPose:
        ok = calibrationHoldLocked(request.calibration_head_pose(), &error);
        *reply.mutable_hold() = holdLocked();
        break;
      case link::proto::ControlRequest::kCalibrationCapture:
        ok = false;
        error = "calibration stills come from the video path, not the head loop";
        break;
      case link::proto::ControlRequest::kSetJpegQuality:
        ok = false;
        error = "JPEG settings belong to the video path, not the head loop";
        break;
      default:
        ok = false;
        error = "empty control request";
    }
    if (nominal) *reply.mutable_nominal() = nominalMappingLocked();
  }
  reply.set_ok(ok);
  reply.set_error(error);
  fillSettings(reply.mutable_settings());
  return reply;
}

}  // namespace telesphere::robot::head
