// SPDX-License-Identifier: MIT
/// @brief Readers of the two ground-truth files of a simulated run: the robot's per-frame truth
///        (robot/stereo/ground_truth_log.h, `telesphere-robot --truth-out`) and the operator app's
///        projection maps (xr/frame_loop/projection_map_recorder.h, `telesphere-xr offscreen --truth-out`).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "xr/render/eye_view.h"

namespace telesphere::truth {

/// One frame the robot sent, as the simulation really had it.
struct RobotTruthRow {
  std::uint64_t sequence = 0;
  std::array<std::int64_t, 2> capture_ns{};                          ///< left, right (robot clock)
  std::array<std::optional<Eigen::Isometry3d>, 2> T_robot_cam_true;  ///< at capture_ns
  bool mapping_set = false;
  Eigen::Isometry3d T_robot_vr = Eigen::Isometry3d::Identity();      ///< in force when sent
};

/// By sequence; nothing, with "<path>:<line>: <what>" in *error, on a missing file or bad row.
std::optional<std::map<std::uint64_t, RobotTruthRow>> loadRobotTruth(const std::string& path, std::string* error);

/// One display frame whose projection maps were recorded.
struct XrTruthFrame {
  std::uint64_t index = 0;
  std::int64_t display_ns = 0;  ///< XR clock
  std::uint64_t stereo_sequence = 0;
  std::int64_t capture_ns = 0;  ///< robot clock
  std::string mode;
  double radius_m = 0, ipd_m = 0;
  xr::render::Fov fov;
  int width = 0, height = 0;              ///< per eye, px
  int image_width = 0, image_height = 0;  ///< camera, px
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_robot_vr_used = Eigen::Isometry3d::Identity();
  std::array<Eigen::Isometry3d, 2> T_robot_cam_stamped{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};  ///< as the frame carried them
};

std::optional<std::vector<XrTruthFrame>> loadXrTruthFrames(const std::string& dir, std::string* error);

/// The frame's maps: 2 eyes × height × width × (x, y), NaN where no camera pixel is shown.
std::optional<std::vector<float>> loadProjectionMap(const std::string& dir, const XrTruthFrame& frame,
                                                    std::string* error);

}  // namespace telesphere::truth
