// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr openxr`'s eye work: what one run draws (the robot's frames or the test
///        scene) and what it does with each eye besides (readback folder, mirror window, its keys).
#pragma once

#include <iostream>
#include <memory>
#include <string>

#include "app/xr_openxr_command.h"
#include "calib/calibration_file.h"
#include "xr/desktop/desktop_window.h"
#include "xr/openxr/openxr_mirror.h"
#include "xr/openxr/openxr_readback_log.h"
#include "xr/openxr/openxr_session.h"
#include "xr/openxr/openxr_test_scene_view.h"
#include "xr/frame_loop/operator_view.h"

namespace telesphere::app {

/// What one run draws (the robot's frames through OperatorView, or the test scene), and what it
/// does with each eye besides: the readback folder, the mirror window and its keys.
class OpenXrEyeWork {
 public:
  OpenXrEyeWork(const OpenXrCommandOptions& o, const xr::render::RenderSettings& settings) : o_(o), settings_(settings) {}

  /// Opens the readback folder; loads the calibration and connects (robot mode) or uploads the
  /// test scene. Exit code or 0.
  int prepare(std::string* error) {
    if (!o_.readback_dir.empty() && !(readback_ = xr::openxr::OpenXrReadbackLog::open(o_.readback_dir, error))) return 1;
    if (o_.test_scene) {
      test_scene_ = xr::openxr::OpenXrTestSceneView::create(settings_, error);
      return test_scene_ ? 0 : 3;
    }
    auto calibration = calib::loadCalibrationFile(o_.calib);
    if (!calibration) {
      *error = calibration.error().describe();
      return 1;
    }
    if (calibration->cameras.size() != 2) {
      *error = o_.calib + ": the calibration has " + std::to_string(calibration->cameras.size()) +
               " camera(s); the operator view needs two";
      return 1;
    }
    xr::frame_loop::OperatorViewOptions options;
    options.endpoints.host = o_.host;
    options.endpoints.base_port = o_.port;
    options.endpoints.credentials = o_.link.credentials;
    options.render = settings_;
    applyXrDepthOptions(o_.depth, options);
    applyVideoLinkOptions(o_.link, options);
    view_ = std::make_unique<xr::frame_loop::OperatorView>(*calibration, options);
    return 0;
  }

  xr::frame_loop::OperatorScene& scene() { return view_ ? static_cast<xr::frame_loop::OperatorScene&>(*view_) : *test_scene_; }
  xr::frame_loop::OperatorView* view() { return view_.get(); }
  xr::openxr::OpenXrMirror& mirror() { return mirror_; }

  void newSession(int session) {
    if (readback_) readback_->newSession(session);
    if (test_scene_) test_scene_->restart();
  }

  bool afterEye(const xr::openxr::OpenXrEye& eye, std::string* error) {
    return !readback_ || readback_->eyeDrawn(eye, scene(), view_.get(), view_ ? view_->settings() : settings_, error);
  }

  void readBack(const xr::openxr::OpenXrEye& eye) {
    if (o_.mirror) mirror_.copyEye(eye);
    std::string error;
    if (readback_ && !readback_->saveImage(eye, &error)) std::cerr << "telesphere-xr openxr: " << error << "\n";
  }

  /// The mirror window between frames: its keys (N nominal, M mode, +/- radius; Escape quits →
  /// false) and the newest eye images.
  bool betweenFrames(xr::desktop::DesktopWindow& window) {
    window.pollEvents();
    (void)window.headInput();  // the head is the headset's; only the commands count here
    const xr::desktop::DesktopCommands c = window.takeCommands();
    if (view_) {
      if (c.capture_nominal) view_->requestCaptureNominal();
      if (c.cycle_mode) view_->requestNextMode();
      if (c.cycle_depth_proxy) view_->cycleDepthProxy();
      if (c.radius_up) view_->requestRadiusScaled(1.25);
      if (c.radius_down) view_->requestRadiusScaled(1.0 / 1.25);
    }
    std::string error;
    if (!mirror_.present(window, &error)) std::cerr << "telesphere-xr openxr: mirror: " << error << "\n";
    return !(c.quit || window.shouldClose());
  }

 private:
  const OpenXrCommandOptions& o_;
  xr::render::RenderSettings settings_;
  std::unique_ptr<xr::frame_loop::OperatorView> view_;
  std::unique_ptr<xr::openxr::OpenXrTestSceneView> test_scene_;
  std::unique_ptr<xr::openxr::OpenXrReadbackLog> readback_;
  xr::openxr::OpenXrMirror mirror_;
};

}  // namespace telesphere::app
