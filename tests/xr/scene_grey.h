// SPDX-License-Identifier: MIT
/// @brief What the depth tests give the sweep and the depth worker (#35): a synthetic scene's grey
///        image through a lens, as the camera would see it (2× supersampled), and the rig's stereo
///        pair as the worker is offered it (both lumas, each camera's pose from the joints). Shared by
///        the sweep's, the depth worker's, the GPU sweep's and the depth proxies' tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "calib/camera_resolution.h"
#include "calib/system_calibration.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "robot/clock/clock.h"
#include "robot/link/link_pose.h"
#include "robot/stereo/stereo_still.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::xr::test_scenes {

/// The grey (8-bit luma) image of `scene` seen from T_world_cam through `lens` at width × height.
inline std::vector<std::uint8_t> greyImage(const std::shared_ptr<robot::cameras::SyntheticScene>& scene, const calib::GenericCamera& lens,
                                           int width, int height, const Eigen::Isometry3d& T_world_cam) {
  robot::clock::SteadyClock clock;
  robot::cameras::SyntheticCameraOptions options;
  options.supersampling = 2;
  const robot::cameras::SyntheticCamera camera(lens, width, height, scene, robot::cameras::fixedPose(T_world_cam), clock, options);
  std::string grey, error;
  EXPECT_TRUE(robot::stereo::toGray8(camera.renderAt(0), &grey, &error)) << error;
  return {grey.begin(), grey.end()};
}

/// The same as a decoded frame's luma plane (no chroma: the depth worker reads only the luma).
inline std::shared_ptr<render::YuvPlanes> lumaPlane(const std::shared_ptr<robot::cameras::SyntheticScene>& scene,
                                                    const calib::GenericCamera& lens, int width, int height,
                                                    const Eigen::Isometry3d& T_world_cam) {
  auto planes = std::make_shared<render::YuvPlanes>();
  planes->width = width;
  planes->height = height;
  planes->y = greyImage(scene, lens, width, height, T_world_cam);
  return planes;
}

/// `rig`'s stereo pair at width × height as the depth worker is offered it, the left camera at
/// p_robot_rig (the rig not turned): each camera's T_robot_cam from `source` (the joints by
/// default), captured 100 ms a sequence number apart.
inline std::shared_ptr<video::DecodedStereoFrame> rigPairAt(const std::shared_ptr<robot::cameras::SyntheticScene>& scene,
                                                            const calib::SystemCalibration& rig, int width, int height,
                                                            const Eigen::Vector3d& p_robot_rig, std::uint64_t sequence,
                                                            link::proto::PoseSource source = link::proto::POSE_SOURCE_JOINT_BUFFER) {
  const Eigen::Isometry3d T_robot_rig{Eigen::Translation3d(p_robot_rig)};
  const Eigen::Isometry3d T_robot_cam[2] = {T_robot_rig, T_robot_rig * *rig.T_cam_l_cam_r};
  auto pair = std::make_shared<video::DecodedStereoFrame>();
  pair->frame.set_sequence(sequence);
  pair->frame.mutable_stamps()->set_capture_ns(1'000'000'000 + static_cast<std::int64_t>(sequence) * 100'000'000);
  link::proto::CameraImage* images[2] = {pair->frame.mutable_left(), pair->frame.mutable_right()};
  for (int i = 0; i < 2; ++i) {
    std::string error;
    const auto lens = calib::atResolution(rig.cameras[i], width, height, &error);
    EXPECT_TRUE(lens) << error;
    if (!lens) return pair;
    (i == 0 ? pair->left : pair->right) = lumaPlane(scene, lens->camera, width, height, T_robot_cam[i]);
    link::toLinkPose(T_robot_cam[i], images[i]->mutable_t_robot_cam());
    images[i]->set_pose_source(source);
  }
  return pair;
}

}  // namespace telesphere::xr::test_scenes
