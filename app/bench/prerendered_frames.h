// SPDX-License-Identifier: MIT
/// @brief Camera frames rendered once, before a measurement, for benchmarks that replay them
///        (robot::ReplayCamera) so that the synthetic renderer's cost stays out of the figures.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "calib/camera_resolution.h"
#include "robot/cameras/debayer.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"

namespace telesphere::bench {

/// The lens of calib/data/sim_calibration.yaml (4K double sphere, 195°) at width×height.
inline calib::CameraCalibration simulatedLens(int width, int height) {
  Eigen::VectorXd p(6);
  p << 930.0, 930.0, 1919.5, 1079.5, -0.18, 0.59;
  const calib::CameraCalibration full{"cam_l", *calib::GenericCamera::create("ds", p), 3840, 2160};
  std::string error;
  return *calib::atResolution(full, width, height, &error);
}

/// The simulated stereo rig: that lens for both cameras, 64 mm baseline (x of cam_l).
inline calib::SystemCalibration simulatedRig(int width, int height) {
  calib::SystemCalibration rig;
  rig.cameras = {simulatedLens(width, height), simulatedLens(width, height)};
  rig.cameras[1].label = "cam_r";
  rig.T_cam_l_cam_r = Eigen::Isometry3d(Eigen::Translation3d(0.064, 0.0, 0.0));
  return rig;
}

/// T_robot_cam of a camera at the default scene's head position looking forward (robot +x),
/// shifted sideways by `y_offset` metres (left +y).
inline Eigen::Isometry3d forwardCameraPose(double y_offset) {
  Eigen::Isometry3d T_robot_cam = Eigen::Isometry3d::Identity();
  // Optical frame: z forward (robot x), x right (robot −y), y down (robot −z).
  T_robot_cam.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T_robot_cam.translation() = robot::cameras::DefaultSceneLayout{}.head_position + Eigen::Vector3d(0.0, y_offset, 0.0);
  return T_robot_cam;
}

/// `count` frames of the default scene, the camera 1 cm further left in each, so consecutive
/// frames differ as a moving head's would.
inline std::vector<robot::cameras::CameraFrame> prerender(int width, int height, double y_offset, int count) {
  const auto lens = simulatedLens(width, height);
  auto scene = std::make_shared<const robot::cameras::SyntheticScene>(robot::cameras::defaultScene());
  std::vector<robot::cameras::CameraFrame> frames;
  robot::clock::SteadyClock clock;
  for (int i = 0; i < count; ++i) {
    robot::cameras::SyntheticCameraOptions options;
    options.threads = 2;
    robot::cameras::SyntheticCamera camera(lens.camera, width, height, scene,
                                  robot::cameras::fixedPose(forwardCameraPose(y_offset + 0.01 * i)), clock, options);
    frames.push_back(camera.renderAt(0));
  }
  return frames;
}

/// What a camera with this colour filter sends of an RGB frame: its raw 8-bit mosaic (#34).
inline robot::cameras::CameraFrame mosaicOf(const robot::cameras::CameraFrame& rgb, robot::cameras::PixelFormat layout) {
  robot::cameras::CameraFrame out = rgb;
  out.format = layout;
  out.stride_bytes = rgb.width;
  out.pixels = std::make_shared<std::vector<std::uint8_t>>(
      robot::cameras::bayerMosaicOf(rgb.pixels->data(), rgb.width, rgb.height, rgb.stride_bytes, layout));
  return out;
}

}  // namespace telesphere::bench
