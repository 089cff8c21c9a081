// SPDX-License-Identifier: MIT
/// @brief What the robot's messages say about the operator's view, read the same way by the live
///        view (OperatorView) and the offline replay of a recording (xr/replay): whether a frame's
///        camera poses were measured, the mode and sphere radius the robot publishes, and the
///        stand-in for the nominal mapping T_robot_vr before the nominal pose is captured.
#pragma once

#include <Eigen/Geometry>

#include "robot/link/telesphere_link.pb.h"
#include "xr/render/eye_view.h"
#include "xr/render/spherical_renderer.h"

namespace telesphere::xr::frame_loop {

/// Both cameras' poses came from joint states at capture time (link POSE_SOURCE_JOINT_BUFFER).
bool cameraPosesMeasured(const link::proto::StereoFrame& frame);

/// `settings` with the visual mode and sphere radius of the robot's state, where they are valid.
render::RenderSettings withRobotSettings(render::RenderSettings settings, const link::proto::RobotState& state);

/// T_robot_vr before a nominal pose exists: the VR frame placed so that the left eye at
/// T_vr_left_eye sits at the left camera's centre of `frame`, looking along its optical axis.
Eigen::Isometry3d standInT_robot_vr(const link::proto::StereoFrame& frame, const Eigen::Isometry3d& T_vr_left_eye);

}  // namespace telesphere::xr::frame_loop
