// SPDX-License-Identifier: MIT
/// @brief The robot's messages read for the operator's view (see robot_view_state.h).
#include "xr/frame_loop/robot_view_state.h"

#include "robot/link/link_pose.h"
#include "robot/link/proto_enums.h"
#include "robot/link/sphere_radius.h"

namespace telesphere::xr::frame_loop {

bool cameraPosesMeasured(const link::proto::StereoFrame& frame) {
  return frame.left().pose_source() == link::proto::POSE_SOURCE_JOINT_BUFFER &&
         frame.right().pose_source() == link::proto::POSE_SOURCE_JOINT_BUFFER;
}

render::RenderSettings withRobotSettings(render::RenderSettings settings, const link::proto::RobotState& state) {
  if (const auto mode = link::fromProto(state.visual_mode())) settings.mode = *mode;
  if (link::acceptedSphereRadius(state.sphere_radius())) settings.radius = state.sphere_radius();
  return settings;
}

Eigen::Isometry3d standInT_robot_vr(const link::proto::StereoFrame& frame, const Eigen::Isometry3d& T_vr_left_eye) {
  return link::fromLinkPose(frame.left().t_robot_cam()) * Eigen::Isometry3d(render::kR_optical_view) * T_vr_left_eye.inverse();
}

}  // namespace telesphere::xr::frame_loop
